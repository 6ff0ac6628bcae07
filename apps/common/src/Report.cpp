#include <apps/Report.h>

#include <algorithm>
#include <fstream>

namespace apps {

double median(std::vector<double> v, double ifEmpty) {
    if (v.empty()) return ifEmpty;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

nlohmann::json vec3Json(const glm::vec3& v) {
    return nlohmann::json::array({v.x, v.y, v.z});
}

void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& report) {
    std::ofstream(path) << report.dump(2) << "\n";
}

} // namespace apps
