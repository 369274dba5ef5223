// glTF 2.0 loading (.gltf and .glb) through tinygltf, hardened for untrusted files.
//
// tinygltf parses the JSON and decodes buffers; it does not check that accessors stay inside their
// buffers or that indices stay inside the vertex range. So nothing is read from a buffer before this
// file has checked the accessor -> bufferView -> buffer chain (indices, component types, byte ranges
// in 64-bit arithmetic, strides), every index value and every position. A .glb's header and chunks are
// checked here too before tinygltf sees them. Any problem is a one-line "<path>: <reason>" error; no
// exception leaves loadGltf.
//
// Hostile files: the JSON's bracket nesting is bounded (kMaxJsonDepth) before tinygltf's recursive
// parser sees it; buffer and image URIs resolve only to regular files inside the scene's folder (after
// realpath, so neither "..", an absolute path nor a symlink leaves it; scenes/gltf_guard.*) unless the
// caller allows more;
// messages are escaped and cut (io::escapeText), with data URIs and the JSON parser's "last read" text
// removed, so an error never echoes the file's bytes.
//
// Mapping: each (glTF mesh, TRIANGLES primitive) becomes one ml::Mesh (its material gives the albedo,
// so primitives cannot share a mesh); each node that uses the mesh becomes one Instance per primitive.
// Primitives of other glTF modes (0..6) are skipped and counted in scene.warnings; a mode outside
// 0..6 is an error, and so is an asset.version other than 2.x. Missing normals become flat
// normals (architectural models are flat-faced).
//
// Mirrored transforms (negative determinant) reverse the winding in world space. When EVERY instance
// is mirrored the asset was authored for a y-down clip space (the Vulkan-Samples building is such a
// scene: upside down under glTF's +Y up); the whole scene is then mirrored in Y, which makes it upright
// and every transform proper, and a warning says so. Instances that remain mirrored get a copy of their
// mesh with reversed triangles, so that world-space winding is counter-clockwise-outward everywhere.
//
// Lights: KHR_lights_punctual lights are used first (up to `lights`); the rest are spotlights placed
// from the seed on the geometry (area-weighted), each above a surface point and aimed at it.
#include "io/safe_io.h"
#include "scenes/gltf_guard.h"
#include "scenes/mesh_utils.h"
#include "scenes/scenes.h"

#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <cstring>
#include <tuple>

#include <climits>
#include <cstdlib>
#include <sys/stat.h>

namespace ml {
namespace {

using namespace gltf_guard;

constexpr uint32_t kMaxLights = 4096;
constexpr uint64_t kMaxElements = uint64_t(1)
                                  << 28; // per accessor; far above real scenes, far below overflow

// Images are irrelevant here (albedo comes from baseColorFactor); skipping their decoding is faster and
// keeps stb_image away from untrusted bytes.
bool ignoreImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                 void*) {
    return true;
}

const char* modeName(int mode) {
    switch (mode) {
    case TINYGLTF_MODE_POINTS:
        return "POINTS";
    case TINYGLTF_MODE_LINE:
        return "LINES";
    case TINYGLTF_MODE_LINE_LOOP:
        return "LINE_LOOP";
    case TINYGLTF_MODE_LINE_STRIP:
        return "LINE_STRIP";
    case TINYGLTF_MODE_TRIANGLE_STRIP:
        return "TRIANGLE_STRIP";
    case TINYGLTF_MODE_TRIANGLE_FAN:
        return "TRIANGLE_FAN";
    default:
        return "unknown";
    }
}

// A validated accessor: element i starts at data + i * stride and holds `components` values of
// `componentType`. Only produced by Loader::view after all range checks.
struct View {
    const unsigned char* data = nullptr;
    uint64_t stride = 0, count = 0;
    int componentType = 0, components = 0;
};

// One (node, primitive) pair before meshes are built.
struct Placement {
    glm::dmat4 world;
    int mesh, primitive;
};

class Loader {
  public:
    Loader(const std::string& path, uint32_t lights, uint32_t seed, const LoadOptions& options)
        : path_(path), lights_(lights), seed_(seed), options_(options) {}

    Result<Scene> run() {
        if (lights_ == 0 || lights_ > kMaxLights)
            return fail(path_ + ": lights must be in 1.." + std::to_string(kMaxLights) + ", got " +
                        std::to_string(lights_));
        if (auto r = parse(); !r) return fail(r.error());
        scene_.name = std::filesystem::path(path_).stem().string();
        if (auto r = checkExtensions(); !r) return fail(r.error());
        if (auto r = collectNodes(); !r) return fail(r.error());
        if (auto r = buildInstances(); !r) return fail(r.error());
        if (scene_.instances.empty()) return fail(path_ + ": no triangle geometry in the scene");
        updateBounds(scene_);
        if (auto r = addFileLights(); !r) return fail(r.error());
        addProceduralLights();
        setCamera();
        for (const auto& [mode, count] : skippedModes_)
            scene_.warnings.push_back(std::to_string(count) + " primitive(s) of mode " + modeName(mode) +
                                      " skipped (only TRIANGLES is loaded)");
        return std::move(scene_);
    }

  private:
    Result<void> error(const std::string& reason) const { return fail(path_ + ": " + reason); }

    Result<void> parse() {
        // Regular files only, under 4 GiB (a .glb's length field is 32 bits).
        auto read = io::readRegularFile(path_, 0xFFFFFFFEull);
        if (!read) return fail(read.error());
        const std::vector<unsigned char>& bytes = read.value();
        if (bytes.empty()) return error("empty file");
        std::string baseDir = std::filesystem::path(path_).parent_path().string();
        UriGuard guard;
        char root[PATH_MAX];
        if (!::realpath(baseDir.empty() ? "." : baseDir.c_str(), root))
            return error("cannot resolve its folder");
        guard.root = root;
        guard.allowOutside = options_.allowOutsideSceneDir;
        tinygltf::TinyGLTF gltf;
        gltf.SetImageLoader(&ignoreImage, nullptr);
        tinygltf::FsCallbacks fs;
        fs.FileExists = &UriGuard::exists;
        fs.ExpandFilePath = &UriGuard::expand;
        fs.ReadWholeFile = &UriGuard::read;
        fs.WriteWholeFile = &UriGuard::write;
        fs.user_data = &guard;
        gltf.SetFsCallbacks(fs);
        std::string err, warn;
        bool ok;
        bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
        if (binary) {
            if (std::string why = checkGlb(bytes); !why.empty()) return error(why);
            if (std::string why = checkJsonDepth(bytes.data() + 20, u32le(&bytes[12])); !why.empty())
                return error(why);
            ok = gltf.LoadBinaryFromMemory(&model_, &err, &warn, bytes.data(), unsigned(bytes.size()),
                                           baseDir);
        } else {
            std::string ext = std::filesystem::path(path_).extension().string();
            if (ext == ".glb" || ext == ".GLB") return error("not a binary glTF (bad magic)");
            if (std::string why = checkJsonDepth(bytes.data(), bytes.size()); !why.empty()) return error(why);
            ok = gltf.LoadASCIIFromString(&model_, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                          unsigned(bytes.size()), baseDir);
        }
        if (!ok && !guard.refused.empty()) return error(guard.refused);
        if (!ok) return error(err.empty() ? "tinygltf could not parse the file" : cleanMessage(err));
        // glTF 2.x only ("major.minor"): a 1.0 file parses with other meanings (no reason is echoed).
        const std::string& version = model_.asset.version;
        if (version.size() < 3 || version[0] != '2' || version[1] != '.' ||
            version.find_first_not_of("0123456789", 2) != std::string::npos)
            return error("asset.version is not 2.x (only glTF 2.0 files are read)");
        if (!guard.refused.empty()) scene_.warnings.push_back(guard.refused); // an image: not needed here
        if (!warn.empty()) scene_.warnings.push_back("tinygltf: " + cleanMessage(warn));
        return {};
    }

    Result<void> checkExtensions() {
        for (const std::string& e : model_.extensionsRequired) {
            if (e == "KHR_draco_mesh_compression" || e == "EXT_meshopt_compression" ||
                e == "KHR_mesh_quantization")
                return error("requires unsupported extension " + e);
            scene_.warnings.push_back("required extension " + e + " ignored");
        }
        return {};
    }

    // Validates a node's local transform and returns it (double precision: deep hierarchies compose
    // without drift).
    Result<void> localMatrix(const tinygltf::Node& node, int index, glm::dmat4& out) const {
        std::string where = "node " + std::to_string(index);
        auto finite = [](const std::vector<double>& v) {
            return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
        };
        if (!finite(node.matrix) || !finite(node.translation) || !finite(node.rotation) ||
            !finite(node.scale))
            return error(where + ": transform is not finite");
        if (!node.matrix.empty()) {
            if (node.matrix.size() != 16) return error(where + ": matrix must have 16 values");
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) out[c][r] = node.matrix[size_t(c * 4 + r)]; // column-major
            return {};
        }
        if (!node.translation.empty() && node.translation.size() != 3)
            return error(where + ": translation must have 3 values");
        if (!node.rotation.empty() && node.rotation.size() != 4)
            return error(where + ": rotation must have 4 values");
        if (!node.scale.empty() && node.scale.size() != 3) return error(where + ": scale must have 3 values");
        glm::dvec3 t(0.0), s(1.0);
        glm::dquat q(1.0, 0.0, 0.0, 0.0); // (w, x, y, z)
        if (!node.translation.empty()) t = {node.translation[0], node.translation[1], node.translation[2]};
        if (!node.scale.empty()) s = {node.scale[0], node.scale[1], node.scale[2]};
        if (!node.rotation.empty()) {
            q = glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
            double len = glm::length(q);
            if (!(len > 0.0)) return error(where + ": rotation is a zero quaternion");
            q = q / len;
        }
        out = glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(q) * glm::scale(glm::dmat4(1.0), s);
        return {};
    }

    // Walks the default scene (or every root node when the file has no scenes), collecting placements.
    Result<void> collectNodes() {
        size_t nodeCount = model_.nodes.size();
        std::vector<int> roots;
        if (!model_.scenes.empty()) {
            int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
            if (size_t(s) >= model_.scenes.size())
                return error("default scene " + std::to_string(s) + " does not exist");
            roots = model_.scenes[size_t(s)].nodes;
        } else {
            std::vector<bool> isChild(nodeCount, false);
            for (const auto& n : model_.nodes)
                for (int c : n.children)
                    if (c >= 0 && size_t(c) < nodeCount) isChild[size_t(c)] = true;
            for (size_t i = 0; i < nodeCount; ++i)
                if (!isChild[i]) roots.push_back(int(i));
        }
        // Explicit stack: a hostile file cannot overflow the call stack. A node reached twice is a cycle
        // or a shared child, both invalid glTF.
        std::vector<bool> visited(nodeCount, false);
        std::vector<std::pair<int, glm::dmat4>> stack;
        for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, glm::dmat4(1.0)});
        while (!stack.empty()) {
            auto [index, parent] = stack.back();
            stack.pop_back();
            if (index < 0 || size_t(index) >= nodeCount)
                return error("node index " + std::to_string(index) + " out of range");
            if (visited[size_t(index)])
                return error("node " + std::to_string(index) + " is reached twice (cycle or shared child)");
            visited[size_t(index)] = true;
            const tinygltf::Node& node = model_.nodes[size_t(index)];
            glm::dmat4 local;
            if (auto r = localMatrix(node, index, local); !r) return r;
            glm::dmat4 world = parent * local;
            if (node.mesh >= 0) {
                if (size_t(node.mesh) >= model_.meshes.size())
                    return error("node " + std::to_string(index) + ": mesh " + std::to_string(node.mesh) +
                                 " out of range");
                const auto& prims = model_.meshes[size_t(node.mesh)].primitives;
                for (size_t p = 0; p < prims.size(); ++p) {
                    // tinygltf reads an absent mode as -1 (the default, triangles); any other value
                    // outside glTF's 0..6 is a broken file, not triangles.
                    if (prims[p].mode < -1 || prims[p].mode > TINYGLTF_MODE_TRIANGLE_FAN)
                        return error("mesh " + std::to_string(node.mesh) + " primitive " + std::to_string(p) +
                                     ": mode " + std::to_string(prims[p].mode) +
                                     " is not a glTF primitive mode (0..6)");
                    int mode = prims[p].mode < 0 ? TINYGLTF_MODE_TRIANGLES : prims[p].mode;
                    if (mode != TINYGLTF_MODE_TRIANGLES) {
                        ++skippedModes_[mode];
                        continue;
                    }
                    placements_.push_back({world, node.mesh, int(p)});
                }
            }
            if (auto ext = node.extensions.find("KHR_lights_punctual"); ext != node.extensions.end()) {
                if (ext->second.Has("light") && ext->second.Get("light").IsInt())
                    lightNodes_.push_back({ext->second.Get("light").Get<int>(), world});
            }
            for (auto it = node.children.rbegin(); it != node.children.rend(); ++it)
                stack.push_back({*it, world});
        }
        return {};
    }

    static uint64_t componentSize(int type) {
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

    // Checks accessor `index` (type `type`, one of `allowed` component types) all the way to its buffer
    // bytes. Every read later goes through the returned View, whose byte range is known to be in bounds.
    Result<void> view(int index, int type, std::initializer_list<int> allowed, View& out) const {
        std::string where = "accessor " + std::to_string(index);
        if (index < 0 || size_t(index) >= model_.accessors.size()) return error(where + " out of range");
        const tinygltf::Accessor& a = model_.accessors[size_t(index)];
        if (a.sparse.isSparse) return error(where + ": sparse accessors are not supported");
        if (a.type != type) return error(where + ": unexpected element type " + std::to_string(a.type));
        if (std::find(allowed.begin(), allowed.end(), a.componentType) == allowed.end())
            return error(where + ": unexpected component type " + std::to_string(a.componentType));
        if (uint64_t(a.count) > kMaxElements)
            return error(where + ": count " + std::to_string(a.count) + " too large");
        if (a.bufferView < 0 || size_t(a.bufferView) >= model_.bufferViews.size())
            return error(where + ": bufferView " + std::to_string(a.bufferView) + " out of range");
        const tinygltf::BufferView& bv = model_.bufferViews[size_t(a.bufferView)];
        if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size())
            return error(where + ": buffer " + std::to_string(bv.buffer) + " out of range");
        const tinygltf::Buffer& buffer = model_.buffers[size_t(bv.buffer)];
        uint64_t bvOffset = bv.byteOffset, bvLength = bv.byteLength;
        if (bvOffset > buffer.data.size() || bvLength > buffer.data.size() - bvOffset)
            return error("bufferView " + std::to_string(a.bufferView) + " [" + std::to_string(bvOffset) +
                         ", +" + std::to_string(bvLength) + ") runs past buffer " +
                         std::to_string(bv.buffer) + " (" + std::to_string(buffer.data.size()) + " bytes)");
        int components = tinygltf::GetNumComponentsInType(uint32_t(a.type));
        if (components <= 0) return error(where + ": bad element type");
        uint64_t element = componentSize(a.componentType) * uint64_t(components);
        // glTF allows byteStride 4..252; the bound also keeps stride * count far from 64-bit overflow.
        if (bv.byteStride > 252)
            return error(where + ": byteStride " + std::to_string(bv.byteStride) + " above 252");
        uint64_t stride = bv.byteStride == 0 ? element : uint64_t(bv.byteStride);
        if (stride < element)
            return error(where + ": byteStride " + std::to_string(stride) + " smaller than element");
        uint64_t offset = a.byteOffset;
        if (a.count > 0) {
            uint64_t end = offset + stride * (uint64_t(a.count) - 1) + element;
            if (offset > bvLength || end > bvLength)
                return error(where + ": " + std::to_string(a.count) + " elements at offset " +
                             std::to_string(offset) + " run past bufferView " + std::to_string(a.bufferView) +
                             " (" + std::to_string(bvLength) + " bytes)");
        }
        out.data = buffer.data.data() + bvOffset + offset;
        out.stride = stride;
        out.count = a.count;
        out.componentType = a.componentType;
        out.components = components;
        return {};
    }

    static glm::vec3 readVec3(const View& v, uint64_t i) {
        float f[3];
        std::memcpy(f, v.data + i * v.stride, sizeof f);
        return {f[0], f[1], f[2]};
    }

    static uint32_t readIndex(const View& v, uint64_t i) {
        const unsigned char* p = v.data + i * v.stride;
        switch (v.componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return p[0];
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t x;
            std::memcpy(&x, p, 2);
            return x;
        }
        default: {
            uint32_t x;
            std::memcpy(&x, p, 4);
            return x;
        }
        }
    }

    // Converts one TRIANGLES primitive after validating all of its data.
    Result<void> convert(int meshIndex, int primIndex, Mesh& out) {
        const tinygltf::Mesh& gm = model_.meshes[size_t(meshIndex)];
        const tinygltf::Primitive& prim = gm.primitives[size_t(primIndex)];
        std::string where = "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(primIndex);
        auto pos = prim.attributes.find("POSITION");
        if (pos == prim.attributes.end()) return error(where + ": no POSITION attribute");
        View pv;
        if (auto r = view(pos->second, TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT}, pv); !r)
            return error(where + ": " + r.error().substr(path_.size() + 2));
        if (pv.count > 0xFFFFFFFFull) return error(where + ": too many vertices");
        out.name = (gm.name.empty() ? "mesh" + std::to_string(meshIndex) : gm.name) + "#" +
                   std::to_string(primIndex);
        out.vertices.resize(size_t(pv.count));
        for (uint64_t i = 0; i < pv.count; ++i) {
            glm::vec3 p = readVec3(pv, i);
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                return error(where + ": position " + std::to_string(i) + " is not finite");
            out.vertices[size_t(i)] = {p, glm::vec3(0.0f)};
        }
        if (prim.indices >= 0) {
            View iv;
            if (auto r = view(prim.indices, TINYGLTF_TYPE_SCALAR,
                              {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                               TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                              iv);
                !r)
                return error(where + " indices: " + r.error().substr(path_.size() + 2));
            if (iv.count % 3 != 0)
                return error(where + ": index count " + std::to_string(iv.count) + " is not a multiple of 3");
            out.indices.resize(size_t(iv.count));
            for (uint64_t i = 0; i < iv.count; ++i) {
                uint32_t x = readIndex(iv, i);
                if (x >= pv.count)
                    return error(where + ": index " + std::to_string(i) + " is not below the vertex count " +
                                 std::to_string(pv.count));
                out.indices[size_t(i)] = x;
            }
        } else {
            if (pv.count % 3 != 0)
                return error(where + ": vertex count " + std::to_string(pv.count) +
                             " is not a multiple of 3");
            out.indices.resize(size_t(pv.count));
            for (uint32_t i = 0; i < uint32_t(pv.count); ++i) out.indices[i] = i;
        }
        bool haveNormals = false;
        if (auto nrm = prim.attributes.find("NORMAL"); nrm != prim.attributes.end()) {
            View nv;
            if (auto r = view(nrm->second, TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT}, nv); !r)
                return error(where + " normals: " + r.error().substr(path_.size() + 2));
            if (nv.count != pv.count) return error(where + ": NORMAL count differs from POSITION count");
            haveNormals = true;
            for (uint64_t i = 0; i < nv.count && haveNormals; ++i) {
                glm::vec3 n = readVec3(nv, i);
                float len = glm::length(n);
                if (!std::isfinite(len) || len < 1e-6f)
                    haveNormals = false;
                else
                    out.vertices[size_t(i)].normal = n / len;
            }
            if (!haveNormals) scene_.warnings.push_back(where + ": invalid normals replaced by flat normals");
        }
        if (!haveNormals) detail::makeFlatNormals(out);
        out.closed = isClosedMesh(out);
        return {};
    }

    // baseColorFactor -> albedo, metallicFactor / roughnessFactor -> metalness / roughness (textures are
    // not read). Without a material: albedo 0.8 (glTF's default is white; 0.8 keeps the default surface
    // from reflecting all light) and, for the same reason, a rough dielectric (glTF's default is a rough
    // metal, black under diffuse light).
    Result<void> material(int material, Instance& inst) const {
        inst.albedo = glm::vec3(0.8f);
        inst.roughness = 1.0f;
        inst.metalness = 0.0f;
        if (material < 0) return {};
        if (size_t(material) >= model_.materials.size())
            return error("material " + std::to_string(material) + " out of range");
        const auto& pbr = model_.materials[size_t(material)].pbrMetallicRoughness;
        const auto& f = pbr.baseColorFactor;
        if (f.size() != 4)
            return error("material " + std::to_string(material) + ": baseColorFactor must have 4 values");
        for (int i = 0; i < 3; ++i) {
            if (!std::isfinite(f[size_t(i)]))
                return error("material " + std::to_string(material) + ": baseColorFactor is not finite");
            inst.albedo[i] = float(std::clamp(f[size_t(i)], 0.0, 1.0));
        }
        if (!std::isfinite(pbr.metallicFactor) || !std::isfinite(pbr.roughnessFactor))
            return error("material " + std::to_string(material) +
                         ": metallicFactor or roughnessFactor is not finite");
        inst.metalness = float(std::clamp(pbr.metallicFactor, 0.0, 1.0));
        inst.roughness = float(std::clamp(pbr.roughnessFactor, 0.0, 1.0));
        return {};
    }

    Result<void> buildInstances() {
        // See the overview: an all-mirrored scene is a y-down asset; mirror it back upright.
        bool allMirrored = !placements_.empty();
        for (const Placement& p : placements_)
            allMirrored = allMirrored && glm::determinant(glm::dmat3(p.world)) < 0.0;
        glm::dmat4 fix(1.0);
        if (allMirrored) {
            fix[1][1] = -1.0;
            scene_.warnings.push_back(
                "every instance is mirrored (y-down asset): scene mirrored in Y to stand upright");
            for (auto& l : lightNodes_) l.second = fix * l.second;
        }
        std::map<std::tuple<int, int, bool>, uint32_t> cache; // (mesh, primitive, reversed) -> scene mesh
        for (const Placement& p : placements_) {
            glm::dmat4 world = fix * p.world;
            double det = glm::determinant(glm::dmat3(world));
            if (!(std::abs(det) > 1e-18)) {
                scene_.warnings.push_back("instance of mesh " + std::to_string(p.mesh) +
                                          " has a degenerate transform: skipped");
                continue;
            }
            bool reversed = det < 0.0;
            auto key = std::make_tuple(p.mesh, p.primitive, reversed);
            auto it = cache.find(key);
            if (it == cache.end()) {
                Mesh mesh;
                if (auto r = convert(p.mesh, p.primitive, mesh); !r) return r;
                if (mesh.indices.empty()) {
                    scene_.warnings.push_back(mesh.name + ": no triangles, skipped");
                    continue;
                }
                if (reversed) {
                    mesh.name += " (mirrored)";
                    for (size_t t = 0; t < mesh.indices.size(); t += 3)
                        std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
                }
                scene_.meshes.push_back(std::move(mesh));
                it = cache.emplace(key, uint32_t(scene_.meshes.size() - 1)).first;
            }
            Instance inst;
            inst.mesh = it->second;
            inst.transform = glm::mat4(world);
            if (auto r =
                    material(model_.meshes[size_t(p.mesh)].primitives[size_t(p.primitive)].material, inst);
                !r)
                return r;
            scene_.instances.push_back(inst);
        }
        return {};
    }

    float sceneSize() const { return std::max(glm::length(scene_.boundsMax - scene_.boundsMin), 1e-3f); }

    // KHR_lights_punctual: position from the node, direction along the node's local -Z.
    Result<void> addFileLights() {
        for (const auto& [index, world] : lightNodes_) {
            if (scene_.lights.size() >= lights_) break;
            if (index < 0 || size_t(index) >= model_.lights.size())
                return error("KHR_lights_punctual light " + std::to_string(index) + " out of range");
            const tinygltf::Light& gl = model_.lights[size_t(index)];
            Light l;
            if (gl.type == "spot")
                l.type = LightKind::Spot;
            else if (gl.type == "point")
                l.type = LightKind::Point;
            else if (gl.type == "directional")
                l.type = LightKind::Directional;
            else
                return error("light " + std::to_string(index) + ": unknown type \"" +
                             io::escapeText(gl.type, 40) + "\"");
            l.position = glm::vec3(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
            glm::vec3 d = glm::vec3(world * glm::dvec4(0.0, 0.0, -1.0, 0.0));
            if (!(glm::length(d) > 0.0f))
                return error("light " + std::to_string(index) + ": degenerate node transform");
            l.direction = glm::normalize(d);
            if (gl.color.size() == 3)
                l.color = glm::vec3(float(gl.color[0]), float(gl.color[1]), float(gl.color[2]));
            l.intensity = float(gl.intensity);
            // glTF: no range (0 here) means infinite, which becomes half the scene; a negative or
            // non-finite range, or cone angles outside (0, pi/2) and [0, outer], are refused, not clamped.
            const std::string which = "light " + std::to_string(index) + ": ";
            if (!std::isfinite(gl.range) || gl.range < 0.0)
                return error(which + "range must be finite and > 0 (or absent)");
            if (!(gl.intensity >= 0.0)) return error(which + "intensity is negative or not finite");
            for (double c : gl.color)
                if (!(c >= 0.0)) return error(which + "colour is negative or not finite");
            l.range = gl.range > 0.0 ? float(gl.range) : 0.5f * sceneSize();
            if (l.type == LightKind::Spot) {
                const double outer = gl.spot.outerConeAngle, inner = gl.spot.innerConeAngle;
                if (!(outer > 0.0 && float(outer) < 1.5707963f))
                    return error(which + "spot outerConeAngle must be in (0, pi/2)");
                if (!(inner >= 0.0 && inner <= outer))
                    return error(which + "spot innerConeAngle must be in [0, outerConeAngle]");
                l.outerAngle = float(outer);
                l.innerAngle = std::min(float(inner), l.outerAngle);
            }
            if (!std::isfinite(l.intensity) || !std::isfinite(l.range) || !std::isfinite(l.color.x) ||
                !std::isfinite(l.color.y) || !std::isfinite(l.color.z) || !std::isfinite(l.position.x) ||
                !std::isfinite(l.position.y) || !std::isfinite(l.position.z))
                return error("light " + std::to_string(index) + ": parameters are not finite");
            scene_.lights.push_back(l);
        }
        return {};
    }

    // Fills up to `lights` with spotlights: pick a surface point (area-weighted over the instance
    // triangles in world space that face up or sideways), hover h = 6-15% of the scene diagonal above it
    // along its normal and aim back at it with a slight random tilt. Range 2-3 h, so the pool reaches the
    // surface and a bit beyond; intensity ~ h^2 keeps the illuminance at the pool similar for every light.
    void addProceduralLights() {
        if (scene_.lights.size() >= lights_) return;
        std::vector<double> cdf;
        std::vector<std::pair<uint32_t, uint32_t>> tri; // (instance, first index)
        double total = 0.0;
        for (uint32_t i = 0; i < scene_.instances.size(); ++i) {
            const Instance& inst = scene_.instances[i];
            const Mesh& m = scene_.meshes[inst.mesh];
            for (uint32_t t = 0; t + 2 < m.indices.size(); t += 3) {
                glm::vec3 a = glm::vec3(inst.transform * glm::vec4(m.vertices[m.indices[t]].position, 1.0f));
                glm::vec3 b =
                    glm::vec3(inst.transform * glm::vec4(m.vertices[m.indices[t + 1]].position, 1.0f));
                glm::vec3 c =
                    glm::vec3(inst.transform * glm::vec4(m.vertices[m.indices[t + 2]].position, 1.0f));
                glm::vec3 cr = glm::cross(b - a, c - a);
                double area = 0.5 * double(glm::length(cr));
                if (!(area > 0.0) || !std::isfinite(area)) continue;
                // Surfaces facing down (undersides of slabs, ceilings) would put the light under the
                // ground or aim it upwards; only floors, roofs and walls receive lights.
                if (cr.y < -0.1f * glm::length(cr)) continue;
                total += area;
                cdf.push_back(total);
                tri.push_back({i, t});
            }
        }
        detail::Pcg32 rng(seed_, 7);
        float size = sceneSize();
        while (scene_.lights.size() < lights_) {
            glm::vec3 p = 0.5f * (scene_.boundsMin + scene_.boundsMax), n(0.0f, 1.0f, 0.0f);
            if (!cdf.empty()) {
                double u = double(rng.uniform()) * total;
                size_t k = size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
                k = std::min(k, cdf.size() - 1);
                const Instance& inst = scene_.instances[tri[k].first];
                const Mesh& m = scene_.meshes[inst.mesh];
                uint32_t t = tri[k].second;
                glm::vec3 a = glm::vec3(inst.transform * glm::vec4(m.vertices[m.indices[t]].position, 1.0f));
                glm::vec3 b =
                    glm::vec3(inst.transform * glm::vec4(m.vertices[m.indices[t + 1]].position, 1.0f));
                glm::vec3 c =
                    glm::vec3(inst.transform * glm::vec4(m.vertices[m.indices[t + 2]].position, 1.0f));
                float r1 = std::sqrt(rng.uniform()), r2 = rng.uniform(); // uniform point in the triangle
                p = a * (1.0f - r1) + b * (r1 * (1.0f - r2)) + c * (r1 * r2);
                glm::vec3 cr = glm::cross(b - a, c - a);
                if (glm::length(cr) > 0.0f) n = glm::normalize(cr);
            }
            float h = size * rng.uniform(0.06f, 0.15f);
            glm::vec3 jitter(rng.uniform(-0.2f, 0.2f), rng.uniform(-0.2f, 0.2f), rng.uniform(-0.2f, 0.2f));
            glm::vec3 dir = -n + jitter;
            if (glm::length(dir) < 1e-3f) dir = -n;
            Light l;
            l.type = LightKind::Spot;
            l.position = p + n * h;
            l.direction = glm::normalize(dir);
            float warmth = rng.uniform();
            l.color = glm::vec3(1.0f, 0.8f + 0.15f * warmth, 0.55f + 0.4f * warmth);
            l.range = h * rng.uniform(2.0f, 3.0f);
            l.intensity = 1.1f * h * h;
            l.outerAngle = rng.uniform(0.5f, 0.8f);
            l.innerAngle = 0.6f * l.outerAngle;
            scene_.lights.push_back(l);
        }
    }

    // Three-quarter view from above and in front, far enough that the bounding sphere fits the view.
    void setCamera() {
        Camera& cam = scene_.camera;
        glm::vec3 centre = 0.5f * (scene_.boundsMin + scene_.boundsMax);
        float radius = 0.5f * sceneSize();
        cam.fovY = 1.0f;
        float distance = radius / std::sin(0.5f * cam.fovY) * 1.05f;
        cam.position = centre + glm::normalize(glm::vec3(0.7f, 0.6f, 1.0f)) * distance;
        cam.target = centre;
        cam.nearPlane = std::max(0.01f, std::min(0.1f, 0.001f * distance));
        cam.farPlane = distance + 2.0f * radius;
    }

    std::string path_;
    uint32_t lights_, seed_;
    LoadOptions options_;
    tinygltf::Model model_;
    Scene scene_;
    std::vector<Placement> placements_;
    std::vector<std::pair<int, glm::dmat4>> lightNodes_;
    std::map<int, uint32_t> skippedModes_;
};

} // namespace

Result<Scene> loadGltf(const std::string& path, uint32_t lights, uint32_t seed, const LoadOptions& options) {
    try {
        return Loader(path, lights, seed, options).run();
    } catch (const std::exception& e) {
        return fail(path + ": " + cleanMessage(e.what()));
    } catch (...) {
        return fail(path + ": unexpected error while loading");
    }
}

} // namespace ml
