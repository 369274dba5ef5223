// Checks of an untrusted glTF file that run before and around tinygltf (scenes/gltf_loader.cpp): the
// JSON's bracket depth (tinygltf's parser recurses per level), a .glb's header and chunks, the
// file-system callbacks that keep buffer and image URIs inside the scene's folder, and the cleaning of
// tinygltf's messages so that an error never echoes the file's bytes.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ml::gltf_guard {

constexpr uint32_t kMaxJsonDepth = 64; // glTF itself needs about 8; extras rarely more than a few

// A tinygltf or JSON message as one safe line (data URIs by their length, no quotes of the file).
std::string cleanMessage(std::string s);
// "" when the JSON's bracket nesting stays within kMaxJsonDepth, else the reason.
std::string checkJsonDepth(const unsigned char* text, size_t size);

// tinygltf file-system callbacks (user_data = the UriGuard) that resolve URIs inside `root` only.
struct UriGuard {
    std::string root;          // realpath of the scene's folder
    bool allowOutside = false; // LoadOptions::allowOutsideSceneDir
    std::string refused;       // the first refusal, reported instead of tinygltf's "File not found"

    bool allowed(const std::string& path, std::string* resolved);
    static std::string expand(const std::string& path, void*);
    static bool exists(const std::string& path, void* self);
    static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* self);
    static bool write(std::string*, const std::string&, const std::vector<unsigned char>&, void*);
};

uint32_t u32le(const unsigned char* p);
// "" when a .glb's header and chunk table are consistent with its size, else the reason.
std::string checkGlb(const std::vector<unsigned char>& bytes);

} // namespace ml::gltf_guard
