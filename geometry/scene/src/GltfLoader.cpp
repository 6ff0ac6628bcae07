// glTF 2.0 / GLB → one world-space MeshData.
// - Nodes of the default scene (or every root node when there is none) are walked with their
//   matrices / TRS composed; every primitive of every mesh is merged, one vertex range each.
// - TRIANGLES are kept as stored; strips and fans are converted to lists, dropping the
//   index-degenerate triangles those encodings use as restarts.
// - Accessors are read through one routine that honours byteStride, normalisation and sparse
//   substitution, and checks every byte range against its buffer (files are untrusted input).
// - A node transform with negative determinant mirrors the geometry, so winding is flipped to keep
//   front faces counter-clockwise.
// - Camera nodes met on the same walk give GltfCameras from their world transform; the list is
//   sorted by node index afterwards (file order, whatever the hierarchy).
#include <geometry/scene/GltfLoader.h>

#include <geometry/core/Error.h>
#include <geometry/core/Limits.h>

#include "GltfChecks.h"
#include "JsonDepth.h"

#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <regex>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_set>

namespace geometry {
namespace {

// Levels of the node hierarchy walked (the root is level 1); real files have a handful.
constexpr int kMaxNodeDepth = 1000;

// Nesting of the glTF JSON (arrays and objects); tinygltf converts extras and extensions by
// recursion, one stack frame per level. A glTF file's own structure is 5 levels deep.
constexpr std::size_t kMaxJsonDepth = 256;

// Elements one accessor may have: the vertices (three per triangle) or indices of a scene at its
// triangle budget (geometry/core/Limits.h). Checked before anything is allocated.
constexpr std::size_t kMaxAccessorCount = 3 * kMaxSceneTriangles;

// Every accessor element as doubles (exact for all glTF component types), row per element.
struct AccessorValues {
    std::size_t count = 0;
    int components = 0;
    int componentType = 0;
    std::vector<double> values; // count * components
    double at(std::size_t i, int c) const { return values[i * components + c]; }
};

class Loader {
public:
    // Without `readMeshes` only cameras are collected (no mesh is required or read).
    Loader(const std::filesystem::path& path, const tinygltf::Model& model, bool readMeshes)
        : mPath(path), mModel(model), mReadMeshes(readMeshes) {}

    GltfContents load(const glm::mat4& transform);

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(mPath.string() + ": " + what);
    }

    AccessorValues readAccessor(int index, const std::string& what) const;
    // A per-vertex attribute `name` of a primitive (`where`) with `vertices` vertices: its type
    // (`typeOk`, else "NAME must be EXPECTED") and count checked before it is read (a count
    // that differs is wrong whatever the data holds), and the count read checked again.
    AccessorValues readVertexAttribute(int index, const std::string& where, const char* name,
                                       std::size_t vertices, const char* expected,
                                       bool (*typeOk)(const tinygltf::Accessor&)) const;
    // Checks the byte range first, then sizes `out` to count * components and fills it.
    void readRaw(const tinygltf::BufferView& view, int viewIndex, std::size_t byteOffset,
                 std::size_t stride, std::size_t count, int componentType, int components,
                 bool normalized, const std::string& what, std::vector<double>& out) const;

    // `node 3 "spawn 1 (info_player_start)"` (the name only when there is one).
    std::string nodeLabel(int nodeIndex) const;
    void walkNodes(int rootIndex, const glm::dmat4& root);
    glm::dmat4 visitNode(int nodeIndex, const glm::dmat4& parent, int depth);
    void addCamera(int nodeIndex, const glm::dmat4& world);
    void addPrimitive(const tinygltf::Primitive& prim, const glm::dmat4& world,
                      const std::string& where);
    std::uint32_t materialIndex(int gltfMaterial);
    int textureIndex(int gltfTexture, const std::string& materialName, bool required);
    glm::mat3 textureTransform(const tinygltf::Value& ext, const std::string& materialName,
                               int& texCoord) const;

    std::filesystem::path mPath;
    const tinygltf::Model& mModel;
    bool mReadMeshes = true;
    MeshData mMesh;
    std::vector<GltfCamera> mCameras;
    int mOrthographic = 0;
    bool mAnyTexcoords = false;
    bool mAnyNormals = false;
    std::map<int, std::uint32_t> mMaterialMap; // glTF material (-1 = default) → ours
    std::map<int, int> mTextureMap;            // glTF texture → MeshData::textures
    std::vector<bool> mVisited;                // nodes walked so far (each at most once)
    struct PathEntry {
        int node;
        glm::dmat4 world;
        std::size_t nextChild;
    };
    std::vector<PathEntry> mWalk; // the walk's current path from the root (cycle check)
};

int componentSize(int type) {
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return 4;
    default:
        return 0;
    }
}

int componentCount(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR:
        return 1;
    case TINYGLTF_TYPE_VEC2:
        return 2;
    case TINYGLTF_TYPE_VEC3:
        return 3;
    case TINYGLTF_TYPE_VEC4:
        return 4;
    case TINYGLTF_TYPE_MAT2:
        return 4;
    case TINYGLTF_TYPE_MAT3:
        return 9;
    case TINYGLTF_TYPE_MAT4:
        return 16;
    default:
        return 0;
    }
}

const char* componentTypeName(int type) {
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
        return "byte";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return "unsigned byte";
    case TINYGLTF_COMPONENT_TYPE_SHORT:
        return "short";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return "unsigned short";
    case TINYGLTF_COMPONENT_TYPE_INT:
        return "int";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        return "unsigned int";
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return "float";
    case TINYGLTF_COMPONENT_TYPE_DOUBLE:
        return "double";
    default:
        return "unknown componentType";
    }
}

const char* typeName(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR:
        return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
        return "VEC2";
    case TINYGLTF_TYPE_VEC3:
        return "VEC3";
    case TINYGLTF_TYPE_VEC4:
        return "VEC4";
    case TINYGLTF_TYPE_MAT2:
        return "MAT2";
    case TINYGLTF_TYPE_MAT3:
        return "MAT3";
    case TINYGLTF_TYPE_MAT4:
        return "MAT4";
    default:
        return "of unknown type";
    }
}

// Shortest round-trip-ish form for messages: 1e+19, 12.5, -3e+07.
std::string formatNumber(double x) {
    std::ostringstream s;
    s << std::setprecision(6) << x;
    return s.str();
}

// One component at p, converted per the glTF normalisation rules when `normalized`.
double decodeComponent(const unsigned char* p, int type, bool normalized) {
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        std::int8_t v;
        std::memcpy(&v, p, 1);
        return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
        std::uint8_t v;
        std::memcpy(&v, p, 1);
        return normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_INT: {
        std::int32_t v;
        std::memcpy(&v, p, 4);
        return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
    }
    default: { // FLOAT (validated by the caller)
        float v;
        std::memcpy(&v, p, 4);
        return v;
    }
    }
}

void Loader::readRaw(const tinygltf::BufferView& view, int viewIndex, std::size_t byteOffset,
                     std::size_t stride, std::size_t count, int componentType, int components,
                     bool normalized, const std::string& what,
                     std::vector<double>& out) const {
    if (view.buffer < 0 || std::size_t(view.buffer) >= mModel.buffers.size()) {
        fail(what + ": bufferView " + std::to_string(viewIndex) + " names a missing buffer");
    }
    const auto& data = mModel.buffers[view.buffer].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
        fail(what + ": bufferView " + std::to_string(viewIndex) + " lies outside its buffer");
    }
    const std::size_t elementBytes = std::size_t(componentSize(componentType)) * components;
    if (count > 0) {
        // Last byte read must stay inside the view; written to avoid overflow on huge counts.
        const std::size_t span = view.byteLength;
        if (byteOffset > span || elementBytes > span - byteOffset ||
            (count - 1) > (span - byteOffset - elementBytes) / std::max<std::size_t>(stride, 1)) {
            fail(what + ": accessor data runs past the end of bufferView " +
                 std::to_string(viewIndex));
        }
    }
    // Only now is the size known to be backed by data: a header claiming millions of elements
    // over a few bytes costs nothing.
    out.assign(count * components, 0.0);
    const unsigned char* base = data.data() + view.byteOffset + byteOffset;
    const int compBytes = componentSize(componentType);
    for (std::size_t i = 0; i < count; ++i) {
        const unsigned char* e = base + i * stride;
        for (int c = 0; c < components; ++c) {
            out[i * components + c] = decodeComponent(e + c * compBytes, componentType, normalized);
        }
    }
}

AccessorValues Loader::readVertexAttribute(int index, const std::string& where, const char* name,
                                           std::size_t vertices, const char* expected,
                                           bool (*typeOk)(const tinygltf::Accessor&)) const {
    const auto count = [&](std::size_t n) {
        return where + ": " + name + " has " + std::to_string(n) + " elements, POSITION " +
               std::to_string(vertices);
    };
    if (index >= 0 && std::size_t(index) < mModel.accessors.size()) {
        const tinygltf::Accessor& acc = mModel.accessors[std::size_t(index)];
        if (!typeOk(acc)) fail(where + ": " + name + " must be " + expected);
        if (acc.count != vertices) fail(count(acc.count));
    }
    const AccessorValues values = readAccessor(index, where + " " + name);
    if (values.count != vertices) fail(count(values.count));
    return values;
}

AccessorValues Loader::readAccessor(int index, const std::string& what) const {
    if (index < 0 || std::size_t(index) >= mModel.accessors.size()) {
        fail(what + ": accessor " + std::to_string(index) + " does not exist");
    }
    const tinygltf::Accessor& acc = mModel.accessors[index];
    const std::string name = what + " (accessor " + std::to_string(index) + ")";
    AccessorValues result;
    result.components = componentCount(acc.type);
    result.componentType = acc.componentType;
    result.count = acc.count;
    if (result.components == 0 || componentSize(acc.componentType) == 0) {
        fail(name + ": unsupported type/componentType");
    }
    // Refuse absurd counts before allocating anything.
    if (acc.count > kMaxAccessorCount) {
        fail(name + ": count " + std::to_string(acc.count) + " is more than the " +
             std::to_string(kMaxAccessorCount) + " elements an accessor may have (" +
             std::to_string(kMaxSceneTriangles) + " triangles a scene)");
    }
    if (acc.bufferView < 0 && !(acc.sparse.isSparse && acc.sparse.count > 0)) {
        fail(name + ": accessor has neither a bufferView nor sparse data (compressed mesh?)");
    }

    // No bufferView means all zeros (only meaningful with sparse substitution below).
    if (acc.bufferView < 0) {
        result.values.assign(acc.count * result.components, 0.0);
    } else {
        if (std::size_t(acc.bufferView) >= mModel.bufferViews.size()) {
            fail(name + ": bufferView " + std::to_string(acc.bufferView) + " does not exist");
        }
        const auto& view = mModel.bufferViews[acc.bufferView];
        const std::size_t packed =
            std::size_t(componentSize(acc.componentType)) * result.components;
        const std::size_t stride = view.byteStride ? view.byteStride : packed;
        if (stride < packed) fail(name + ": byteStride smaller than one element");
        readRaw(view, acc.bufferView, acc.byteOffset, stride, acc.count, acc.componentType,
                result.components, acc.normalized, name, result.values);
    }

    if (acc.sparse.isSparse && acc.sparse.count > 0) {
        const auto& sp = acc.sparse;
        const std::size_t n = std::size_t(sp.count);
        if (n > acc.count) fail(name + ": sparse count exceeds accessor count");
        const int idxType = sp.indices.componentType;
        if (idxType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            idxType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            idxType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
            fail(name + ": sparse indices must be unsigned byte/short/int");
        }
        auto view = [&](int v) -> const tinygltf::BufferView& {
            if (v < 0 || std::size_t(v) >= mModel.bufferViews.size()) {
                fail(name + ": sparse bufferView " + std::to_string(v) + " does not exist");
            }
            return mModel.bufferViews[v];
        };
        if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0) {
            fail(name + ": negative sparse byteOffset");
        }
        std::vector<double> indices;
        readRaw(view(sp.indices.bufferView), sp.indices.bufferView,
                std::size_t(sp.indices.byteOffset), std::size_t(componentSize(idxType)), n, idxType,
                1, false, name + " sparse indices", indices);
        std::vector<double> values;
        readRaw(view(sp.values.bufferView), sp.values.bufferView, std::size_t(sp.values.byteOffset),
                std::size_t(componentSize(acc.componentType)) * result.components, n,
                acc.componentType, result.components, acc.normalized, name + " sparse values",
                values);
        for (std::size_t k = 0; k < n; ++k) {
            if (indices[k] >= double(acc.count)) {
                fail(name + ": sparse index " + std::to_string(std::size_t(indices[k])) +
                     " out of range (count " + std::to_string(acc.count) + ")");
            }
            const std::size_t dst = std::size_t(indices[k]) * result.components;
            std::copy_n(values.begin() + k * result.components, result.components,
                        result.values.begin() + dst);
        }
    }
    return result;
}

glm::dmat4 localMatrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        glm::dmat4 m;
        std::copy(node.matrix.begin(), node.matrix.end(), glm::value_ptr(m)); // column-major
        return m;
    }
    glm::dmat4 m(1.0);
    if (node.translation.size() == 3) {
        m = glm::translate(
            m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
    }
    if (node.rotation.size() == 4) {
        // glTF stores quaternions as x, y, z, w; glm's constructor takes w first.
        const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
        m = m * glm::mat4_cast(glm::normalize(q));
    }
    if (node.scale.size() == 3) {
        m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    }
    return m;
}

std::string Loader::nodeLabel(int nodeIndex) const {
    const std::string& name = mModel.nodes[nodeIndex].name;
    return "node " + std::to_string(nodeIndex) + (name.empty() ? "" : " \"" + name + "\"");
}

// Depth first, children in order, with an explicit stack: a recursive walk's frame is a few KiB
// (more under AddressSanitizer, where a chain of kMaxNodeDepth levels overflowed the 8 MiB stack).
void Loader::walkNodes(int rootIndex, const glm::dmat4& root) {
    mWalk.clear();
    mWalk.push_back({rootIndex, visitNode(rootIndex, root, 0), 0});
    while (!mWalk.empty()) {
        PathEntry& top = mWalk.back();
        const std::vector<int>& children = mModel.nodes[top.node].children;
        if (top.nextChild == children.size()) {
            mWalk.pop_back();
            continue;
        }
        const int child = children[top.nextChild++];
        const glm::dmat4 world = visitNode(child, top.world, int(mWalk.size()));
        mWalk.push_back({child, world, 0});
    }
}

// One node: its checks, camera and meshes; returns its world transform for its children.
glm::dmat4 Loader::visitNode(int nodeIndex, const glm::dmat4& parent, int depth) {
    if (nodeIndex < 0 || std::size_t(nodeIndex) >= mModel.nodes.size()) {
        fail("node " + std::to_string(nodeIndex) + " does not exist");
    }
    if (std::any_of(mWalk.begin(), mWalk.end(),
                    [&](const PathEntry& e) { return e.node == nodeIndex; })) {
        fail("node hierarchy has a cycle through node " + std::to_string(nodeIndex));
    }
    // glTF 2.0 §3.5.3: the nodes form disjoint trees, so a node is met once. A node listed by two
    // parents (or twice by one) would be walked once per path to it: a chain of n nodes, each
    // naming the next twice, is 2^n visits.
    if (mVisited.empty()) mVisited.assign(mModel.nodes.size(), false);
    if (mVisited[nodeIndex]) {
        fail(nodeLabel(nodeIndex) +
             " is reached a second time: a node may have only one parent and be listed once "
             "(glTF 2.0 node hierarchy: disjoint trees)");
    }
    mVisited[nodeIndex] = true;
    // Bounded so a hostile chain cannot make the walk (and its cycle check) unbounded.
    if (depth >= kMaxNodeDepth) {
        fail("node hierarchy is deeper than " + std::to_string(kMaxNodeDepth) +
             " levels (node " + std::to_string(nodeIndex) + " is at level " +
             std::to_string(depth + 1) + "); no cycle, but not supported");
    }
    const tinygltf::Node& node = mModel.nodes[nodeIndex];
    const glm::dmat4 world = parent * localMatrix(node);
    for (int i = 0; i < 16; ++i) {
        if (!std::isfinite(glm::value_ptr(world)[i])) {
            fail(nodeLabel(nodeIndex) + " has a non-finite transform");
        }
    }
    if (node.camera >= 0) addCamera(nodeIndex, world);
    if (mReadMeshes && node.mesh >= 0) {
        if (std::size_t(node.mesh) >= mModel.meshes.size()) {
            fail("node " + std::to_string(nodeIndex) + " references missing mesh " +
                 std::to_string(node.mesh));
        }
        const auto& mesh = mModel.meshes[node.mesh];
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
            addPrimitive(mesh.primitives[p], world,
                         "mesh " + std::to_string(node.mesh) +
                             (mesh.name.empty() ? "" : " \"" + mesh.name + "\"") + " primitive " +
                             std::to_string(p));
        }
    }
    return world;
}

void Loader::addCamera(int nodeIndex, const glm::dmat4& world) {
    const tinygltf::Node& node = mModel.nodes[nodeIndex];
    const std::string where = nodeLabel(nodeIndex) + ": camera " + std::to_string(node.camera);
    if (std::size_t(node.camera) >= mModel.cameras.size()) fail(where + " does not exist");
    const tinygltf::Camera& cam = mModel.cameras[node.camera];
    if (cam.type == "orthographic") {
        ++mOrthographic; // no orthographic views here; counted so callers can say so
        return;
    }
    if (cam.type != "perspective") fail(where + ": unknown camera type \"" + cam.type + "\"");
    const double yfov = cam.perspective.yfov;
    if (!(std::isfinite(yfov) && yfov > 0.0 && yfov < std::numbers::pi)) {
        fail(where + ": yfov " + std::to_string(yfov) + " is not in (0, pi) radians");
    }
    // The camera looks along its local -Z with +Y up (glTF 2.0 §3.10.1); directions take the
    // linear part only.
    const glm::dvec3 eye(world[3]);
    const glm::dvec3 forward = -glm::dvec3(world[2]);
    const glm::dvec3 up(world[1]);
    const double forwardLen = glm::length(forward), upLen = glm::length(up);
    if (!(forwardLen > 0.0 && std::isfinite(forwardLen))) {
        fail(where + ": the node's world transform has no view direction (zero scale)");
    }
    if (!(upLen > 0.0 && std::isfinite(upLen))) {
        fail(where + ": the node's world transform has no up direction (zero scale)");
    }
    GltfCamera out;
    out.name = node.name;
    out.node = nodeIndex;
    out.camera.eye = glm::vec3(eye);
    const glm::vec3 f(forward / forwardLen);
    out.camera.up = glm::vec3(up / upLen);
    // A step that float keeps distinct from the eye wherever the eye is (a unit step is lost in
    // rounding far from the origin).
    const float step = std::max(1.0f, 1e-3f * glm::length(out.camera.eye));
    out.camera.target = out.camera.eye + step * f;
    out.camera.fovYDeg = float(yfov * 180.0 / std::numbers::pi);
    auto finite = [](const glm::vec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    if (!finite(out.camera.eye) || !finite(out.camera.target)) {
        fail(where + ": the eye position is not finite in single precision");
    }
    // Only a sheared (near-singular) transform can do this; the same bound as scene cameras.
    if (!(glm::length(glm::cross(f, out.camera.up)) > 1e-4f)) {
        fail(where + ": the view and up directions are parallel (degenerate transform)");
    }
    mCameras.push_back(std::move(out));
}

void Loader::addPrimitive(const tinygltf::Primitive& prim, const glm::dmat4& world,
                          const std::string& where) {
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        static const char* names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
        const std::string modeName =
            mode >= 0 && mode < 4 ? names[mode] : "mode " + std::to_string(mode);
        fail(where + ": primitive mode " + modeName +
             " is not supported (only triangles, strips and fans cast shadows)");
    }

    const auto posIt = prim.attributes.find("POSITION");
    if (posIt == prim.attributes.end()) fail(where + ": no POSITION attribute");
    {
        const int a = posIt->second;
        if (a < 0 || std::size_t(a) >= mModel.accessors.size()) {
            fail(where + ": POSITION accessor " + std::to_string(a) + " does not exist");
        }
        const auto& acc = mModel.accessors[a];
        if (acc.type != TINYGLTF_TYPE_VEC3 || acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
            fail(where + ": POSITION must be float VEC3 (quantized positions are not supported)");
        }
    }
    // Budgets before anything is read (geometry/core/Limits.h): the triangles the index stream will
    // give, and vertices, of which a mesh within the triangle budget uses at most three per
    // triangle.
    {
        const std::size_t vertices = mModel.accessors[posIt->second].count;
        std::size_t indices = vertices;
        if (prim.indices >= 0 && std::size_t(prim.indices) < mModel.accessors.size())
            indices = mModel.accessors[prim.indices].count;
        const std::size_t triangles = mode == TINYGLTF_MODE_TRIANGLES ? indices / 3
                                      : indices >= 2                  ? indices - 2
                                                                      : 0;
        if (mMesh.triangles.size() + triangles > kMaxSceneTriangles) {
            fail(where + ": " + std::to_string(triangles) + " triangles bring the file to " +
                 std::to_string(mMesh.triangles.size() + triangles) + ", more than the " +
                 std::to_string(kMaxSceneTriangles) + " a scene may have");
        }
        if (mMesh.positions.size() + vertices > 3 * kMaxSceneTriangles) {
            fail(where + ": " + std::to_string(vertices) + " vertices bring the file to " +
                 std::to_string(mMesh.positions.size() + vertices) + ", more than the " +
                 std::to_string(3 * kMaxSceneTriangles) +
                 " (three per triangle of the budget) a scene may have");
        }
    }
    const AccessorValues pos = readAccessor(posIt->second, where + " POSITION");
    const std::size_t base = mMesh.positions.size();
    if (base + pos.count > std::size_t(UINT32_MAX)) fail(where + ": too many vertices");

    for (std::size_t i = 0; i < pos.count; ++i) {
        const glm::dvec3 p(pos.at(i, 0), pos.at(i, 1), pos.at(i, 2));
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            fail(where + ": POSITION " + std::to_string(i) + " is NaN or infinite");
        }
        const glm::dvec3 w = glm::dvec3(world * glm::dvec4(p, 1.0));
        const glm::vec3 f(w);
        if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z)) {
            fail(where + ": POSITION " + std::to_string(i) + " is not finite after transform");
        }
        for (int axis = 0; axis < 3; ++axis) {
            if (std::abs(w[axis]) <= double(kMaxCoordinate)) continue;
            const bool moved = w[axis] != p[axis];
            fail(where + ": POSITION (accessor " + std::to_string(posIt->second) + ") vertex " +
                 std::to_string(i) + " has " + "xyz"[axis] + " = " + formatNumber(w[axis]) +
                 (moved ? " after the node transforms" : "") + ", outside [-" +
                 formatNumber(kMaxCoordinate) + ", " + formatNumber(kMaxCoordinate) +
                 "]: coordinates that large cannot be rendered in single precision");
        }
        mMesh.positions.push_back(f);
    }

    // TEXCOORD_0: float, or normalized unsigned byte/short (glTF 2.0 §3.7.2.1).
    const auto uvIt = prim.attributes.find("TEXCOORD_0");
    if (uvIt != prim.attributes.end()) {
        const AccessorValues uv = readVertexAttribute(
            uvIt->second, where, "TEXCOORD_0", pos.count,
            "VEC2 of float or normalized unsigned byte/short", [](const tinygltf::Accessor& acc) {
                return acc.type == TINYGLTF_TYPE_VEC2 &&
                       (acc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                        (acc.normalized &&
                         (acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                          acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)));
            });
        // Earlier primitives without texcoords get zeros so the arrays stay parallel.
        mMesh.texcoords.resize(base, glm::vec2(0.0f));
        for (std::size_t i = 0; i < uv.count; ++i) {
            glm::vec2 t(float(uv.at(i, 0)), float(uv.at(i, 1)));
            if (!std::isfinite(t.x) || !std::isfinite(t.y)) t = glm::vec2(0.0f);
            mMesh.texcoords.push_back(t);
        }
        mAnyTexcoords = true;
    }

    // NORMAL: float VEC3 (glTF 2.0 §3.7.2.1), for shading only. Normals transform by the
    // inverse transpose of the world matrix's linear part, then are renormalised; a zero normal
    // (some exporters write them for degenerate triangles) leaves shading to the face normal.
    const auto normalIt = prim.attributes.find("NORMAL");
    if (normalIt != prim.attributes.end()) {
        const AccessorValues nv = readVertexAttribute(
            normalIt->second, where, "NORMAL", pos.count, "VEC3 of float",
            [](const tinygltf::Accessor& acc) {
                return acc.type == TINYGLTF_TYPE_VEC3 &&
                       acc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
            });
        const glm::dmat3 linear(world);
        const bool invertible = std::abs(glm::determinant(linear)) > 0.0;
        const glm::dmat3 normalMatrix =
            invertible ? glm::transpose(glm::inverse(linear)) : glm::dmat3(1.0);
        mMesh.normals.resize(base, glm::vec3(0.0f));
        for (std::size_t i = 0; i < nv.count; ++i) {
            const glm::dvec3 n(nv.at(i, 0), nv.at(i, 1), nv.at(i, 2));
            if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) {
                fail(where + ": NORMAL " + std::to_string(i) + " is NaN or infinite");
            }
            const glm::dvec3 w = normalMatrix * n;
            const double len = glm::length(w);
            // Single precision: a normal whose length underflows or overflows as a float has
            // no direction to keep.
            const glm::vec3 unit = invertible && len > 1e-30 && std::isfinite(len)
                                       ? glm::vec3(w / len)
                                       : glm::vec3(0.0f);
            mMesh.normals.push_back(std::isfinite(unit.x) && std::isfinite(unit.y) &&
                                            std::isfinite(unit.z)
                                        ? unit
                                        : glm::vec3(0.0f));
        }
        mAnyNormals = true;
    }

    // Index stream: explicit, or 0..count-1. The type is checked before the data is read, so a
    // wrong type is named as such (a FLOAT index accessor over 2-byte data would otherwise
    // "run past the end" of its view).
    std::vector<std::uint32_t> idx;
    if (prim.indices >= 0) {
        if (std::size_t(prim.indices) < mModel.accessors.size()) {
            const tinygltf::Accessor& acc = mModel.accessors[prim.indices];
            const int t = acc.componentType;
            if (acc.type != TINYGLTF_TYPE_SCALAR || (t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                                     t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                                     t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
                fail(where + ": indices (accessor " + std::to_string(prim.indices) + ") are " +
                     componentTypeName(t) + " " + typeName(acc.type) +
                     "; indices must be SCALAR unsigned byte, short or int");
            }
        }
        const AccessorValues ia = readAccessor(prim.indices, where + " indices");
        idx.reserve(ia.count);
        for (std::size_t i = 0; i < ia.count; ++i) {
            const double v = ia.values[i];
            if (v >= double(pos.count)) {
                fail(where + ": index " + std::to_string(std::uint64_t(v)) + " at position " +
                     std::to_string(i) + " is out of range (" + std::to_string(pos.count) +
                     " vertices)");
            }
            idx.push_back(std::uint32_t(v));
        }
    } else {
        idx.resize(pos.count);
        for (std::size_t i = 0; i < pos.count; ++i)
            idx[i] = std::uint32_t(i);
    }

    // glTF 2.0 §3.7.2.1 primitive topologies.
    std::vector<glm::uvec3> tris;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (idx.size() % 3 != 0) {
            fail(where + ": TRIANGLES with " + std::to_string(idx.size()) +
                 " indices (not a multiple of 3)");
        }
        for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
            tris.emplace_back(idx[i], idx[i + 1], idx[i + 2]);
        }
    } else {
        for (std::size_t i = 0; i + 2 < idx.size(); ++i) {
            glm::uvec3 t;
            if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                // Odd triangles swap their first two vertices to keep one winding.
                t = (i % 2 == 0) ? glm::uvec3(idx[i], idx[i + 1], idx[i + 2])
                                 : glm::uvec3(idx[i + 1], idx[i], idx[i + 2]);
            } else {
                t = glm::uvec3(idx[i + 1], idx[i + 2], idx[0]);
            }
            // Strips use repeated indices as restarts; those triangles have no area.
            if (t.x == t.y || t.y == t.z || t.x == t.z) continue;
            tris.push_back(t);
        }
    }

    // A mirroring transform turns counter-clockwise into clockwise; swap to restore it.
    const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
    const std::uint32_t material = materialIndex(prim.material);
    const Material& m = mMesh.materials[material];
    if (m.alphaTested() && m.baseColorTexture >= 0 && uvIt == prim.attributes.end())
        fail(where + ": material \"" + m.name +
             "\" is alpha-tested through a texture but the primitive has no TEXCOORD_0");
    const auto b = std::uint32_t(base);
    for (const auto& t : tris) {
        if (mirrored) {
            mMesh.triangles.emplace_back(b + t.x, b + t.z, b + t.y);
        } else {
            mMesh.triangles.emplace_back(b + t.x, b + t.y, b + t.z);
        }
        mMesh.triangleMaterial.push_back(material);
    }
}

std::uint32_t Loader::materialIndex(int gltfMaterial) {
    if (gltfMaterial >= 0 && std::size_t(gltfMaterial) >= mModel.materials.size()) {
        fail("material " + std::to_string(gltfMaterial) + " does not exist");
    }
    const int key = gltfMaterial < 0 ? -1 : gltfMaterial;
    if (auto it = mMaterialMap.find(key); it != mMaterialMap.end()) return it->second;

    Material m;
    if (key < 0) {
        m.name = "default"; // glTF default material: opaque white, single-sided
    } else {
        const tinygltf::Material& g = mModel.materials[key];
        m.name = g.name.empty() ? "material " + std::to_string(key) : g.name;
        if (g.alphaMode == "MASK") {
            m.alphaMode = AlphaMode::Mask;
        } else if (g.alphaMode == "BLEND") {
            m.alphaMode = AlphaMode::Blend;
        } else if (g.alphaMode == "OPAQUE" || g.alphaMode.empty()) {
            m.alphaMode = AlphaMode::Opaque;
        } else {
            fail("material \"" + m.name + "\": unknown alphaMode \"" + g.alphaMode + "\"");
        }
        // BLEND has no cutoff in glTF; shadows and the G-buffer test it as MASK at 0.5.
        m.alphaCutoff = m.alphaMode == AlphaMode::Blend ? 0.5f : float(g.alphaCutoff);
        if (!std::isfinite(m.alphaCutoff)) fail("material \"" + m.name + "\": alphaCutoff is not finite");
        m.doubleSided = g.doubleSided;
        const auto& f = g.pbrMetallicRoughness.baseColorFactor;
        if (f.size() == 4)
            m.baseColor = glm::vec4(float(f[0]), float(f[1]), float(f[2]), float(f[3]));
        const tinygltf::TextureInfo& info = g.pbrMetallicRoughness.baseColorTexture;
        if (info.index >= 0) {
            // Alpha-tested materials need their texture; for opaque ones it is only decoration.
            const bool required = m.alphaMode != AlphaMode::Opaque;
            m.baseColorTexture = textureIndex(info.index, m.name, required);
            int texCoord = info.texCoord;
            if (const auto ext = info.extensions.find("KHR_texture_transform");
                ext != info.extensions.end())
                m.baseColorUvTransform = textureTransform(ext->second, m.name, texCoord);
            // Only TEXCOORD_0 is read: an alpha mask read through another set would be silently
            // wrong, a decoration only looks wrong.
            if (required && m.baseColorTexture >= 0 && texCoord != 0)
                fail("material \"" + m.name + "\": base colour texture uses TEXCOORD_" +
                     std::to_string(texCoord) + " (only TEXCOORD_0 is read)");
        }
    }
    const auto index = std::uint32_t(mMesh.materials.size());
    mMesh.materials.push_back(std::move(m));
    mMaterialMap[key] = index;
    return index;
}

// KHR_texture_transform on a textureInfo: uv' = T(offset) R(rotation) S(scale) uv, composed as
// the extension specifies; its texCoord (when given) replaces the textureInfo's.
glm::mat3 Loader::textureTransform(const tinygltf::Value& ext, const std::string& materialName,
                                   int& texCoord) const {
    const std::string what = "material \"" + materialName + "\": KHR_texture_transform";
    if (!ext.IsObject()) fail(what + " is not an object");
    auto number = [&](const tinygltf::Value& v, const char* key) {
        if (!v.IsNumber()) fail(what + ": " + key + " must be a number");
        const double x = v.GetNumberAsDouble();
        if (!std::isfinite(float(x))) fail(what + ": " + key + " is not finite in single precision");
        return float(x);
    };
    auto pair = [&](const char* key, glm::vec2 fallback) {
        if (!ext.Has(key)) return fallback;
        const tinygltf::Value& v = ext.Get(key);
        if (!v.IsArray() || v.ArrayLen() != 2) fail(what + ": " + key + " must be two numbers");
        return glm::vec2(number(v.Get(0), key), number(v.Get(1), key));
    };
    const glm::vec2 offset = pair("offset", glm::vec2(0.0f));
    const glm::vec2 scale = pair("scale", glm::vec2(1.0f));
    const float rotation = ext.Has("rotation") ? number(ext.Get("rotation"), "rotation") : 0.0f;
    if (ext.Has("texCoord")) {
        const tinygltf::Value& t = ext.Get("texCoord");
        if (!t.IsInt() || t.GetNumberAsInt() < 0) fail(what + ": texCoord must be an index");
        texCoord = t.GetNumberAsInt();
    }
    const float c = std::cos(rotation), s = std::sin(rotation);
    const glm::mat3 translate(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1); // column-major
    // (x, y) -> (x cos + y sin, -x sin + y cos): the direction the extension's own example
    // needs (offset [0, 1], rotation pi/2, scale 0.5 selects the lower-left quadrant).
    const glm::mat3 rotate(c, -s, 0, s, c, 0, 0, 0, 1);
    const glm::mat3 scaling(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
    return translate * rotate * scaling;
}

TextureWrap wrapMode(int gl, const std::string& what, const std::filesystem::path& path) {
    switch (gl) {
    case TINYGLTF_TEXTURE_WRAP_REPEAT:
        return TextureWrap::Repeat;
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
        return TextureWrap::ClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
        return TextureWrap::MirroredRepeat;
    default:
        throw InputError(path.string() + ": " + what + " has unknown wrap mode " +
                         std::to_string(gl));
    }
}

int Loader::textureIndex(int gltfTexture, const std::string& materialName, bool required) {
    if (auto it = mTextureMap.find(gltfTexture); it != mTextureMap.end()) return it->second;
    auto missing = [&](const std::string& why) {
        if (required) fail("material \"" + materialName + "\": base colour texture " + why);
        // An opaque material's texture only colours the image: drawn without it, but said.
        std::fprintf(stderr, "warning: %s: material \"%s\": base colour texture %s; drawn without it\n",
                     mPath.string().c_str(), materialName.c_str(), why.c_str());
        mTextureMap[gltfTexture] = -1;
        return -1;
    };
    if (std::size_t(gltfTexture) >= mModel.textures.size()) {
        return missing(std::to_string(gltfTexture) + " does not exist");
    }
    const int source = mModel.textures[gltfTexture].source;
    if (source < 0 || std::size_t(source) >= mModel.images.size()) {
        return missing("has no image source");
    }
    const tinygltf::Image& img = mModel.images[source];
    const int comps = img.component;
    const int bytesPer = img.bits == 16 ? 2 : 1;
    if (img.width <= 0 || img.height <= 0 || comps < 1 || comps > 4 ||
        (img.bits != 8 && img.bits != 16) ||
        img.image.size() < std::size_t(img.width) * img.height * comps * bytesPer) {
        return missing(
            "image " + std::to_string(source) +
            (img.uri.empty() || img.uri.rfind("data:", 0) == 0
                 ? std::string(" could not be decoded")
                 // Our decoder refuses undecodable images: an external one was not read.
                 : " (" + img.uri + ") could not be read (no such file beside the model?)"));
    }

    TextureImage tex;
    tex.width = img.width;
    tex.height = img.height;
    if (const int sampler = mModel.textures[gltfTexture].sampler; sampler >= 0) {
        if (std::size_t(sampler) >= mModel.samplers.size())
            fail("texture " + std::to_string(gltfTexture) + ": sampler " +
                 std::to_string(sampler) + " does not exist");
        const tinygltf::Sampler& s = mModel.samplers[sampler];
        const std::string what = "sampler " + std::to_string(sampler);
        tex.wrapS = wrapMode(s.wrapS, what, mPath);
        tex.wrapT = wrapMode(s.wrapT, what, mPath);
    }
    const std::size_t pixels = std::size_t(img.width) * img.height;
    tex.rgba8.resize(pixels * 4);
    // Expand grey / grey+alpha / RGB to RGBA8; 16-bit channels keep their high byte.
    auto channel = [&](std::size_t p, int c) -> std::uint8_t {
        const std::size_t off = (p * comps + c) * bytesPer;
        if (bytesPer == 1) return img.image[off];
        std::uint16_t v;
        std::memcpy(&v, img.image.data() + off, 2);
        return std::uint8_t(v >> 8);
    };
    for (std::size_t p = 0; p < pixels; ++p) {
        std::uint8_t* d = tex.rgba8.data() + p * 4;
        if (comps <= 2) {
            d[0] = d[1] = d[2] = channel(p, 0);
            d[3] = comps == 2 ? channel(p, 1) : 255;
        } else {
            d[0] = channel(p, 0);
            d[1] = channel(p, 1);
            d[2] = channel(p, 2);
            d[3] = comps == 4 ? channel(p, 3) : 255;
        }
    }
    const int index = int(mMesh.textures.size());
    mMesh.textures.push_back(std::move(tex));
    mTextureMap[gltfTexture] = index;
    return index;
}

GltfContents Loader::load(const glm::mat4& transform) {
    // extensionsRequired was checked on the JSON (detail::checkGltfDocument), before tinygltf.
    if (mReadMeshes && mModel.meshes.empty()) fail("no meshes");

    mMesh.name = mPath.stem().string();
    const glm::dmat4 root(transform);
    std::vector<int> roots;
    if (mModel.defaultScene >= 0 && std::size_t(mModel.defaultScene) < mModel.scenes.size()) {
        roots = mModel.scenes[mModel.defaultScene].nodes;
    } else {
        // No default scene: every node that is nobody's child is a root.
        std::vector<bool> isChild(mModel.nodes.size(), false);
        for (const auto& n : mModel.nodes) {
            for (int c : n.children) {
                if (c >= 0 && std::size_t(c) < isChild.size()) isChild[c] = true;
            }
        }
        for (std::size_t i = 0; i < mModel.nodes.size(); ++i) {
            if (!isChild[i]) roots.push_back(int(i));
        }
    }
    for (int r : roots)
        walkNodes(r, root);

    if (mReadMeshes && mMesh.triangles.empty())
        fail("no triangles (no node of the scene draws a triangle mesh)");
    if (mAnyTexcoords) {
        mMesh.texcoords.resize(mMesh.positions.size(), glm::vec2(0.0f));
    } else {
        mMesh.texcoords.clear();
    }
    if (mAnyNormals) {
        mMesh.normals.resize(mMesh.positions.size(), glm::vec3(0.0f));
    } else {
        mMesh.normals.clear();
    }
    GltfContents result;
    result.mesh = std::move(mMesh);
    result.cameras = std::move(mCameras);
    std::stable_sort(result.cameras.begin(), result.cameras.end(),
                     [](const GltfCamera& a, const GltfCamera& b) { return a.node < b.node; });
    for (std::size_t i = 0; i < result.cameras.size(); ++i) {
        if (result.cameras[i].name.empty()) result.cameras[i].name = "camera " + std::to_string(i);
    }
    result.orthographicCameras = mOrthographic;
    return result;
}

// The folder a model may read external files from: its own and the folders below it. Buffer and
// image URIs are untrusted input: "../../etc/passwd", an absolute path or a symlink out of the
// folder must not read another file (nor reveal its size in an error), and a FIFO or device
// inside it must not be opened (a read that blocks forever, or never ends). An empty folder
// (in-memory input without one) contains nothing: every external file is refused.
class ModelFolder {
public:
    explicit ModelFolder(const std::filesystem::path& folder) : mBase(folder.string()) {
        if (!folder.empty()) mRoot = resolve(folder);
    }
    const std::filesystem::path& root() const { return mRoot; }

    // `file` absolute, with symlinks and ".." resolved; empty when it cannot be resolved (then
    // nothing is inside it, and it is inside nothing).
    static std::filesystem::path resolve(const std::filesystem::path& file) {
        std::error_code ec;
        const std::filesystem::path absolute = std::filesystem::absolute(file, ec);
        if (ec) return {};
        std::filesystem::path p = std::filesystem::weakly_canonical(absolute, ec);
        return ec ? std::filesystem::path() : p;
    }
    bool contains(const std::filesystem::path& resolved) const {
        if (mRoot.empty() || resolved.empty()) return false;
        const std::filesystem::path rel = resolved.lexically_relative(mRoot);
        return !rel.empty() && *rel.begin() != "..";
    }
    // Something at `resolved` that is not a regular file (a FIFO, device, socket or folder).
    static bool special(const std::filesystem::path& resolved) {
        std::error_code ec;
        const auto status = std::filesystem::status(resolved, ec);
        return !ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status);
    }

    // tinygltf's file callbacks, refusing what lies outside (user data: this). tinygltf also
    // looks for a file missing beside the model in the working directory; that is refused too.
    tinygltf::FsCallbacks callbacks() {
        return {.FileExists = &fileExists,
                .ExpandFilePath = &expandFilePath,
                .ReadWholeFile = &readWholeFile,
                .WriteWholeFile = nullptr,
                .user_data = this};
    }
    // tinygltf reads '+' in a URI as a space (form encoding); glTF's URIs are RFC 3986, where it
    // is a plus sign. `uri` as tinygltf decodes it is read as `decoded` instead.
    void readAs(const std::string& tinygltfName, const std::string& decoded) {
        mRenamed[tinygltfName] = decoded;
    }
    // The first file refused (resolved), empty when none was; `refusedWhy` says why.
    const std::filesystem::path& refused() const { return mRefused; }
    const std::string& refusedWhy() const { return mRefusedWhy; }

private:
    void refuse(const std::filesystem::path& resolved, const std::string& why) {
        if (!mRefused.empty()) return;
        mRefused = resolved;
        mRefusedWhy = why;
    }
    std::string outsideWhy() const {
        return mRoot.empty() ? "no external file may be read (the glTF data has no folder)"
                             : "outside the model's folder " + mRoot.string();
    }
    // tinygltf asks for JoinPath(folder, name) and then JoinPath(".", name): the same joins,
    // with the name as RFC 3986 decodes it.
    static std::string join(const std::string& folder, const std::string& name) {
        if (folder.empty()) return name;
        return folder.back() == '/' ? folder + name : folder + "/" + name;
    }
    static std::string expandFilePath(const std::string& file, void* self) {
        const auto& folder = *static_cast<const ModelFolder*>(self);
        for (const auto& [tinygltfName, decoded] : folder.mRenamed) {
            for (const std::string& base : {folder.mBase, std::string(".")}) {
                if (file == join(base, tinygltfName)) return join(base, decoded);
            }
        }
        return file;
    }
    static bool fileExists(const std::string& file, void* self) {
        auto& folder = *static_cast<ModelFolder*>(self);
        const std::filesystem::path resolved = resolve(file);
        std::error_code ec;
        if (!folder.contains(resolved)) {
            if (std::filesystem::exists(resolved, ec)) folder.refuse(resolved, folder.outsideWhy());
            return false;
        }
        if (special(resolved)) {
            folder.refuse(resolved, "not a regular file");
            return false;
        }
        return tinygltf::FileExists(file, nullptr);
    }
    static bool readWholeFile(std::vector<unsigned char>* out, std::string* err,
                              const std::string& file, void* self) {
        auto& folder = *static_cast<ModelFolder*>(self);
        const std::filesystem::path resolved = resolve(file);
        if (!folder.contains(resolved)) {
            folder.refuse(resolved, folder.outsideWhy());
            if (err) *err += "outside the model's folder";
            return false;
        }
        if (special(resolved)) {
            folder.refuse(resolved, "not a regular file");
            if (err) *err += "not a regular file";
            return false;
        }
        return tinygltf::ReadWholeFile(out, err, file, nullptr);
    }

    std::string mBase; // the folder as tinygltf is given it
    std::filesystem::path mRoot;
    std::map<std::string, std::string> mRenamed; // tinygltf's decoding -> RFC 3986's
    std::filesystem::path mRefused;
    std::string mRefusedWhy;
};

// Every buffer and image URI of the glTF JSON is a data: URI or a relative path to a regular
// file that stays in `folder`; an InputError naming the key otherwise. JSON that does not parse
// is left to tinygltf, whose error is better (the file callbacks still guard it). Registers
// with `folder` the URIs tinygltf would decode differently (a '+').
void checkUris(const std::string& origin, const nlohmann::json& doc, ModelFolder& folder) {
    std::map<std::string, std::string> tinygltfNames; // tinygltf's decoding -> the URI
    for (const char* list : {"buffers", "images"}) {
        const auto it = doc.find(list);
        if (it == doc.end() || !it->is_array()) continue;
        for (std::size_t i = 0; i < it->size(); ++i) {
            const nlohmann::json& entry = (*it)[i];
            if (!entry.is_object() || !entry.contains("uri") || !entry["uri"].is_string()) continue;
            const std::string uri = entry["uri"].get<std::string>();
            if (uri.rfind("data:", 0) == 0) continue;
            const std::string key = std::string(list) + "[" + std::to_string(i) + "].uri '" + uri +
                                    "'";
            auto refuse = [&](const std::string& why) {
                throw InputError(origin + ": " + key + " " + why +
                                 ": a glTF file may read only files in its own folder or below "
                                 "it, and data: URIs");
            };
            const std::optional<std::string> rfc = detail::percentDecode(uri);
            if (!rfc) {
                throw InputError(origin + ": " + key +
                                 " has a malformed escape ('%' must be followed by two hex "
                                 "digits)");
            }
            const std::string& decoded = *rfc;
            if (decoded.empty()) continue; // tinygltf reports it
            const std::string tinygltfName = detail::tinygltfDecode(uri);
            if (const auto [it, fresh] = tinygltfNames.emplace(tinygltfName, uri);
                !fresh && detail::percentDecode(it->second) != rfc) {
                throw InputError(origin + ": " + key + " and the URI '" + it->second +
                                 "' differ only by '+' against a space or %20; such names are "
                                 "not supported together");
            }
            if (tinygltfName != decoded) folder.readAs(tinygltfName, decoded);
            static const std::regex scheme(R"(^[A-Za-z][A-Za-z0-9+.\-]*:.*)");
            if (std::regex_match(decoded, scheme)) refuse("is a URL, not a relative path");
            if (decoded.front() == '/' || decoded.front() == '\\') refuse("is an absolute path");
            if (folder.root().empty()) {
                refuse("names an external file, and this glTF data has no folder to read it from");
            }
            const std::filesystem::path resolved = ModelFolder::resolve(folder.root() / decoded);
            if (!folder.contains(resolved)) {
                refuse("leads outside the model's folder " + folder.root().string() +
                       (resolved.empty() ? std::string() : " (to " + resolved.string() + ")"));
            }
            if (ModelFolder::special(resolved)) {
                throw InputError(origin + ": " + key + " is not a regular file (" +
                                 resolved.string() +
                                 " is a FIFO, device, socket or folder); buffers and images "
                                 "must be files");
            }
        }
    }
}

// "'glTX' (67 6c 54 58)": the first bytes of a file, for a message.
std::string describeBytes(std::span<const unsigned char> bytes, std::size_t n) {
    std::ostringstream text, hex;
    for (std::size_t i = 0; i < std::min(n, bytes.size()); ++i) {
        const unsigned char c = bytes[i];
        text << (c >= 32 && c < 127 ? char(c) : '.');
        hex << (i ? " " : "") << std::hex << std::setw(2) << std::setfill('0') << int(c);
    }
    return "'" + text.str() + "' (" + hex.str() + ")";
}

std::uint32_t readU32(std::span<const unsigned char> bytes, std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4); // GLB is little-endian, as is every target here
    return v;
}

// The GLB container (glTF 2.0 §4.4): a 12-byte header (magic, version, total length), a JSON
// chunk, then optionally a BIN chunk, each chunk an 8-byte header (length, type) and its data.
// Checked here, before tinygltf, whose own checks let a BIN chunk run 8 bytes past the data and
// whose messages do not say which length is wrong. Returns the JSON chunk.
std::string_view checkGlbLayout(const std::string& origin, std::span<const unsigned char> bytes) {
    auto fail = [&](const std::string& what) {
        throw InputError(origin + ": malformed GLB: " + what);
    };
    const std::size_t size = bytes.size();
    if (size < 20) {
        fail("only " + std::to_string(size) +
             " bytes; a GLB has a 12-byte header and an 8-byte JSON chunk header at least");
    }
    if (const std::uint32_t version = readU32(bytes, 4); version != 2) {
        fail("version " + std::to_string(version) + " (only glTF 2.0 GLB is read)");
    }
    const std::uint64_t length = readU32(bytes, 8);
    if (length > size) {
        fail("the header gives a length of " + std::to_string(length) + " bytes but there are " +
             std::to_string(size) + " (truncated?)");
    }
    const std::uint64_t jsonLength = readU32(bytes, 12);
    if (std::memcmp(bytes.data() + 16, "JSON", 4) != 0) {
        fail("the first chunk is of type " + describeBytes(bytes.subspan(16, 4), 4) +
             ", not 'JSON'");
    }
    if (jsonLength == 0) fail("the JSON chunk is empty");
    if (20 + jsonLength > length) {
        fail("the JSON chunk's length " + std::to_string(jsonLength) + " runs past the end (" +
             std::to_string(length - 20) + " bytes follow its header)");
    }
    const std::uint64_t binAt = 20 + jsonLength;
    if (binAt < length) {
        if (binAt + 8 > length) {
            fail(std::to_string(length - binAt) +
                 " bytes after the JSON chunk, too few for a chunk header (8 bytes)");
        }
        const std::uint64_t binLength = readU32(bytes, std::size_t(binAt));
        if (binAt + 8 + binLength > length) {
            fail("the chunk after the JSON chunk claims " + std::to_string(binLength) +
                 " bytes but " + std::to_string(length - binAt - 8) + " follow its header");
        }
    }
    return {reinterpret_cast<const char*>(bytes.data() + 20), std::size_t(jsonLength)};
}

// Refuses JSON nested deeper than kMaxJsonDepth before any parser recurses into it.
void checkJsonDepth(const std::string& origin, std::string_view json) {
    const detail::JsonDepth d = detail::jsonNestingDepth(json, kMaxJsonDepth);
    if (d.depth > kMaxJsonDepth) {
        throw InputError(origin + ": glTF JSON is nested deeper than " +
                         std::to_string(kMaxJsonDepth) + " levels (at byte " +
                         std::to_string(d.offset) + "); not supported");
    }
}

// Parses a glTF (binary or JSON, told by its content) and walks it once. `name` stands for the
// file in messages; external files are read from `folder` only.
GltfContents parseBytes(std::span<const unsigned char> bytes, const std::filesystem::path& folder,
                        const std::filesystem::path& name, const glm::mat4& transform,
                        bool readMeshes) {
    const std::string origin = name.string();
    // tinygltf takes the length as an unsigned int.
    if (bytes.size() > std::numeric_limits<unsigned int>::max())
        throw InputError(origin + ": glTF file too large (4 GiB at most)");
    // Decide binary vs JSON from the content, not the extension: a mislabelled file should still
    // load. Garbage gets tinygltf's JSON parse error, unless it is named .glb: then its magic is
    // what is wrong.
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    std::size_t first = bytes.size() >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB &&
                                bytes[2] == 0xBF
                            ? 3 // UTF-8 byte order mark
                            : 0;
    while (first < bytes.size() && std::isspace(bytes[first]))
        ++first;
    const bool looksJson = first < bytes.size() && bytes[first] == '{';
    std::string ext = name.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (!binary && !looksJson && ext == ".glb") {
        throw InputError(origin + ": not a binary glTF file: it begins with " +
                         describeBytes(bytes, 4) + " where a GLB begins with the magic 'glTF'");
    }

    // The JSON, for the depth and URI checks: all of a .gltf, the first chunk of a GLB.
    const std::string_view json =
        binary ? checkGlbLayout(origin, bytes)
               : std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    checkJsonDepth(origin, json);
    ModelFolder modelFolder(folder);
    // JSON that does not parse, or is not an object, is left to tinygltf, whose message says
    // where.
    const nlohmann::json doc = nlohmann::json::parse(json, nullptr, false);
    if (doc.is_object()) {
        detail::checkGltfDocument(origin, doc);
        checkUris(origin, doc, modelFolder);
    }

    tinygltf::TinyGLTF gltf;
    gltf.SetFsCallbacks(modelFolder.callbacks());
    detail::ImageDecoder images;
    gltf.SetImageLoader(&detail::ImageDecoder::decode, &images);
    tinygltf::Model model;
    std::string err, warn;
    const std::string baseDir = folder.string();
    const bool ok =
        binary ? gltf.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(),
                                           static_cast<unsigned int>(bytes.size()), baseDir)
               : gltf.LoadASCIIFromString(&model, &err, &warn,
                                          reinterpret_cast<const char*>(bytes.data()),
                                          static_cast<unsigned int>(bytes.size()), baseDir);
    if (!modelFolder.refused().empty()) {
        throw InputError(origin + ": a buffer or image file resolves to " +
                         modelFolder.refused().string() + ", " + modelFolder.refusedWhy() +
                         ": a glTF file may read only files in its own folder or below it, and "
                         "data: URIs");
    }
    if (!images.refusal().empty()) throw InputError(origin + ": " + images.refusal());
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == '\r'))
            err.pop_back();
        throw InputError(origin + ": glTF parse error: " +
                         (err.empty() ? std::string("unknown error") : err));
    }
    return Loader(name, model, readMeshes).load(transform);
}

// Reads the file and parses it with its own folder as the one external files may come from.
GltfContents parseAndLoad(const std::filesystem::path& path, const glm::mat4& transform,
                          bool readMeshes) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        throw InputError(path.string() + ": glTF file not found");
    }
    std::vector<unsigned char> bytes;
    {
        std::ifstream in(path, std::ios::binary);
        if (!in) throw InputError(path.string() + ": cannot open glTF file");
        const auto size = std::filesystem::file_size(path, ec);
        if (ec || size > std::numeric_limits<unsigned int>::max())
            throw InputError(path.string() + ": glTF file too large (4 GiB at most)");
        bytes.resize(size);
        in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size));
        if (!in) throw InputError(path.string() + ": cannot read glTF file");
    }
    const std::filesystem::path parent = path.parent_path();
    return parseBytes(bytes, parent.empty() ? std::filesystem::path(".") : parent, path,
                      transform, readMeshes); // "a.gltf": its folder is the working directory
}

} // namespace

MeshData loadGltf(const std::filesystem::path& path, const glm::mat4& transform) {
    return parseAndLoad(path, transform, true).mesh;
}

GltfContents loadGltfWithCameras(const std::filesystem::path& path, const glm::mat4& transform) {
    return parseAndLoad(path, transform, true);
}

std::vector<GltfCamera> loadGltfCameras(const std::filesystem::path& path,
                                        const glm::mat4& transform) {
    return parseAndLoad(path, transform, false).cameras;
}

GltfContents parseGltf(std::span<const unsigned char> bytes, const std::filesystem::path& folder,
                       const std::string& name, const glm::mat4& transform) {
    return parseBytes(bytes, folder, name, transform, true);
}

} // namespace geometry
