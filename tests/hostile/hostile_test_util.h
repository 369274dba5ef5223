// Generators for the hostile-input tests and the fuzzers (tests/fuzz/): small valid inputs built in
// memory (a tetrahedron glTF / GLB, a bake file per method from synthetic maps), a per-process temp
// folder, and a runner for the command line that returns its exit status and stderr.
#pragma once
#include "../static/static_test_util.h"
#include "shadows/static/bake_file.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace ml::hostile {

// A fresh folder per process (ctest runs tests in parallel processes), removed at exit.
inline std::filesystem::path tempDir() {
    struct Dir {
        std::filesystem::path path;
        Dir() : path(std::filesystem::temp_directory_path() / ("ml_hostile_" + std::to_string(::getpid()))) {
            std::filesystem::remove_all(path);
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

inline void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(bytes.data(), std::streamsize(bytes.size()));
}
inline std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// ---- glTF ----

// The tetrahedron's buffer: 4 float3 positions (48 bytes) then 12 u16 indices (24 bytes).
inline std::string tetraBin() {
    const float p[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const uint16_t i[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    std::string b(reinterpret_cast<const char*>(p), sizeof p);
    b.append(reinterpret_cast<const char*>(i), sizeof i);
    return b;
}

inline std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < in.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(in[i])) << 16;
        if (i + 1 < in.size()) v |= uint32_t(uint8_t(in[i + 1])) << 8;
        if (i + 2 < in.size()) v |= uint8_t(in[i + 2]);
        out += t[(v >> 18) & 63], out += t[(v >> 12) & 63];
        out += i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
        out += i + 2 < in.size() ? t[v & 63] : '=';
    }
    return out;
}

// A tetrahedron scene. `buffer` is the buffer object's members after byteLength (e.g. a "uri"), or
// empty for a GLB's BIN chunk; `extraTop` more top-level members, each followed by a comma.
inline std::string tetraJson(const std::string& buffer, const std::string& extraTop = "",
                             const std::string& nodeExtra = "") {
    return R"({"asset": {"version": "2.0"}, )" + extraTop +
           R"("scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0)" + nodeExtra +
           R"(}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"},
               {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"}],
 "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 24}],
 "buffers": [{"byteLength": 72)" +
           (buffer.empty() ? "" : ", " + buffer) + "}]}";
}
inline std::string dataUri(const std::string& bin) {
    return "\"uri\": \"data:application/octet-stream;base64," + base64(bin) + "\"";
}

inline void putU32(std::string& s, uint32_t v) {
    for (int i = 0; i < 4; ++i) s += char((v >> (8 * i)) & 0xFF);
}
// A .glb: header, JSON chunk (space-padded to 4 bytes), BIN chunk (zero-padded; none when empty).
inline std::string glb(std::string json, std::string bin) {
    while (json.size() % 4) json += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string out = "glTF";
    putU32(out, 2);
    putU32(out, uint32_t(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size())));
    putU32(out, uint32_t(json.size()));
    putU32(out, 0x4E4F534Au);
    out += json;
    if (bin.empty()) return out; // no BIN chunk
    putU32(out, uint32_t(bin.size()));
    putU32(out, 0x004E4942u);
    out += bin;
    return out;
}

// ---- bake files ----

// Records of synthetic maps at 64^2 (the smallest CPVS resolution), no scene needed.
inline BakeFile syntheticBake(StaticMethod method, uint32_t records = 2, uint32_t seed = 1) {
    BakeFile f;
    f.scene = {"night-city", 256, 7};
    f.method = method;
    f.resolution = 64;
    for (uint32_t k = 0; k < records; ++k) {
        BakeRecord r;
        r.light = 2 * k + 1;
        r.method = method;
        r.resolution = 64;
        r.frustum.view = glm::lookAt(glm::vec3(k, 10.0f, 1.0f), glm::vec3(k, 0.0f, 0.0f), glm::vec3(0, 1, 0));
        r.frustum.fov = 1.1f;
        r.frustum.nearPlane = 0.05f;
        r.frustum.farPlane = 12.0f + float(k);
        StaticEncodeOptions o;
        o.nearPlane = r.frustum.nearPlane, o.farPlane = r.frustum.farPlane;
        auto enc = encodeStatic(method, stest::syntheticMap(64, seed + 100 * k, k % 2 == 0), o);
        if (enc) r.data = enc.value();
        f.records.push_back(std::move(r));
    }
    return f;
}

// ---- the command line ----
#ifdef ML_EXE

struct Run {
    int status = -1;      // exit status; 128 + signal when killed
    std::string out, err; // stdout, stderr
};
// Runs `manylights ARGS` (a shell command line: quote arguments yourself) with a timeout.
inline Run runCli(const std::string& args, int timeoutSeconds = 60) {
    const std::string errFile = (tempDir() / "cli_stderr.txt").string();
    const std::string outFile = (tempDir() / "cli_stdout.txt").string();
    const std::string cmd = "timeout -s KILL " + std::to_string(timeoutSeconds) + " " + ML_EXE + " " + args +
                            " >" + outFile + " 2>" + errFile + " </dev/null";
    const int raw = std::system(cmd.c_str());
    Run r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + (WIFSIGNALED(raw) ? WTERMSIG(raw) : 0);
    r.err = readBytes(errFile);
    r.out = readBytes(outFile);
    return r;
}
#endif

} // namespace ml::hostile
