// What the apps' reports share: the median of timings, vectors as JSON, and writing a report.
#pragma once

#include <geometry/core/Types.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <limits>
#include <vector>

namespace apps {

// The median of `values` (the mean of the two middle ones for an even count); `ifEmpty` when
// there are none.
double median(std::vector<double> values,
              double ifEmpty = std::numeric_limits<double>::quiet_NaN());

// [x, y, z].
nlohmann::json vec3Json(const glm::vec3& v);

// `report` as indented JSON and a newline into `path` (replaced).
void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& report);

} // namespace apps
