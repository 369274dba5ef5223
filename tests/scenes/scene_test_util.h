// Helpers shared by the scenes tests: paths of the shared assets, a per-process temp directory,
// byte-exact scene serialisation (for determinism checks) and small file writers.
#pragma once
#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include "tests/common/shared_scenes.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace ml::test {

inline std::string sharedScene(const char* name) {
    return sharedScenePath(name);
}

// A fresh directory per test process (ctest runs tests in parallel processes), removed at exit.
inline std::filesystem::path tempDir() {
    struct Dir {
        std::filesystem::path path;
        Dir()
            : path(std::filesystem::temp_directory_path() /
                   ("ml_scenes_tests_" + std::to_string(::getpid()))) {
            std::filesystem::create_directories(path);
        }
        ~Dir() {
            std::error_code ignored;
            std::filesystem::remove_all(path, ignored);
        }
    };
    static Dir dir;
    return dir.path;
}

inline std::string writeFile(const std::string& name, const std::string& bytes) {
    std::string path = (tempDir() / name).string();
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    return path;
}

inline std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Field-by-field bytes of a scene: structs have padding with unspecified contents, so they are never
// copied whole.
class Bytes {
  public:
    template <class T> void put(const T& v) { out_.append(reinterpret_cast<const char*>(&v), sizeof v); }
    void put(const std::string& s) {
        put(uint64_t(s.size()));
        out_ += s;
    }
    const std::string& str() const { return out_; }

  private:
    std::string out_;
};

inline std::string sceneBytes(const Scene& s) {
    Bytes b;
    b.put(s.name);
    for (const Mesh& m : s.meshes) {
        b.put(m.name);
        for (const Vertex& v : m.vertices) b.put(v.position), b.put(v.normal);
        for (uint32_t i : m.indices) b.put(i);
        b.put(m.closed);
    }
    for (const Instance& i : s.instances)
        b.put(i.mesh), b.put(i.transform), b.put(i.albedo), b.put(i.dynamic);
    for (const Light& l : s.lights) {
        b.put(l.type), b.put(l.position), b.put(l.direction), b.put(l.color), b.put(l.intensity),
            b.put(l.range);
        b.put(l.outerAngle), b.put(l.innerAngle), b.put(l.dynamic), b.put(l.attachedInstance);
        b.put(l.localPosition), b.put(l.localDirection);
    }
    for (const CarPath& c : s.cars) {
        b.put(c.instance), b.put(c.speed), b.put(c.phase);
        for (const glm::vec3& w : c.waypoints) b.put(w);
    }
    b.put(s.camera.position), b.put(s.camera.target), b.put(s.camera.fovY), b.put(s.camera.nearPlane);
    b.put(s.camera.farPlane), b.put(s.boundsMin), b.put(s.boundsMax);
    return b.str();
}

inline bool finite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Every light usable by the renderer: finite, unit direction, positive range, a cone that opens less
// than a hemisphere with inner <= outer.
inline void expectValidLights(const Scene& s) {
    for (size_t i = 0; i < s.lights.size(); ++i) {
        const Light& l = s.lights[i];
        SCOPED_TRACE("light " + std::to_string(i));
        ASSERT_TRUE(finite(l.position) && finite(l.direction) && finite(l.color));
        ASSERT_NEAR(glm::length(l.direction), 1.0f, 1e-4f);
        ASSERT_TRUE(std::isfinite(l.intensity) && l.intensity > 0.0f);
        ASSERT_TRUE(std::isfinite(l.range) && l.range > 0.0f);
        ASSERT_GE(l.color.x, 0.0f);
        ASSERT_GE(l.color.y, 0.0f);
        ASSERT_GE(l.color.z, 0.0f);
        ASSERT_GT(l.color.x + l.color.y + l.color.z, 0.0f);
        if (l.type == LightKind::Spot) {
            ASSERT_GE(l.innerAngle, 0.0f);
            ASSERT_LE(l.innerAngle, l.outerAngle);
            ASSERT_GT(l.outerAngle, 0.0f);
            ASSERT_LT(l.outerAngle, 1.5707964f);
        }
    }
}

// A loader error: present, one line, naming the file.
inline void expectOneLineError(const Result<Scene>& r, const std::string& path) {
    ASSERT_FALSE(r.ok()) << path << " loaded but should not";
    EXPECT_NE(r.error().find(path), std::string::npos) << r.error();
    EXPECT_EQ(r.error().find('\n'), std::string::npos) << r.error();
    EXPECT_GT(r.error().size(), path.size() + 2) << "no reason given: " << r.error();
}

} // namespace ml::test
