#include "scenes/gltf_guard.h"

#include "io/safe_io.h"

#include <climits>
#include <cstdlib>
#include <cstring>
#include <sys/stat.h>

namespace ml::gltf_guard {

// A tinygltf or JSON message as one safe line: data URIs replaced by their length, the JSON parser's
// "last read: '...'" quote of the file dropped, control characters escaped, long text cut.
std::string cleanMessage(std::string s) {
    for (size_t at = s.find("data:"); at != std::string::npos; at = s.find("data:", at + 1)) {
        size_t end = at;
        while (end < s.size() && !std::isspace(static_cast<unsigned char>(s[end])) && s[end] != '"' &&
               s[end] != '\'')
            ++end;
        const std::string note = "data:<" + std::to_string(end - at) + "-byte data URI>";
        s.replace(at, end - at, note);
        at += note.size() - 1;
    }
    if (size_t q = s.find("; last read:"); q != std::string::npos) s.erase(q, s.find('\n', q) - q);
    for (char& c : s)
        if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return io::escapeText(s, 240);
}

// JSON bracket depth, scanned before tinygltf's recursive parser runs (nlohmann::json recurses once
// per level: ~30,000 nested arrays overflow the stack). Brackets inside strings do not count.
std::string checkJsonDepth(const unsigned char* text, size_t size) {
    uint32_t depth = 0;
    bool inString = false, escaped = false;
    for (size_t i = 0; i < size; ++i) {
        const unsigned char c = text[i];
        if (inString) {
            if (escaped)
                escaped = false;
            else if (c == '\\')
                escaped = true;
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth)
                return "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels at byte " +
                       std::to_string(i);
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return {};
}

std::string UriGuard::expand(const std::string& path, void*) {
    return path; // no wordexp, no ~
}

// Resolves `path`; false (and `refused` set) when it leaves the folder or is not a regular file.
bool UriGuard::allowed(const std::string& path, std::string* resolved) {
    char buf[PATH_MAX];
    if (!::realpath(path.c_str(), buf)) {
        // tinygltf joins an absolute URI to the folder ("dir//etc/x"), which then does not resolve: say
        // why it is refused rather than "File not found".
        if (refused.empty() && !allowOutside && path.find("//") != std::string::npos)
            refused = "URI '" + io::escapeText(path, 120) + "' is an absolute path, outside the scene's " +
                      "folder (refused; a trusted scene may allow it: --allow-outside-scene-dir)";
        return false;
    }
    const std::string real = buf;
    const std::string uri = io::escapeText(path, 120);
    const std::string prefix = root == "/" ? root : root + "/";
    if (!allowOutside && real != root && real.compare(0, prefix.size(), prefix) != 0) {
        if (refused.empty())
            refused = "URI '" + uri + "' resolves outside the scene's folder (refused; a trusted " +
                      "scene may allow it: --allow-outside-scene-dir)";
        return false;
    }
    struct stat st {};
    if (::stat(buf, &st) != 0 || !S_ISREG(st.st_mode)) {
        if (refused.empty()) refused = "URI '" + uri + "' is not a regular file";
        return false;
    }
    if (resolved) *resolved = real;
    return true;
}

bool UriGuard::exists(const std::string& path, void* self) {
    return static_cast<UriGuard*>(self)->allowed(path, nullptr);
}

bool UriGuard::read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* self) {
    UriGuard& guard = *static_cast<UriGuard*>(self);
    std::string real;
    if (!guard.allowed(path, &real)) {
        if (err) *err = "refused";
        return false;
    }
    auto bytes = io::readRegularFile(real, 0xFFFFFFFFull);
    if (!bytes) {
        // Said in full (the size against the 4 GiB limit of a buffer's 32-bit length) instead of
        // tinygltf's message; the path is the resolved one inside the scene's folder, no file bytes.
        if (guard.refused.empty()) guard.refused = bytes.error() + " (a glTF buffer is at most 4 GiB)";
        if (err) *err = "cannot read";
        return false;
    }
    *out = std::move(bytes.value());
    return true;
}

bool UriGuard::write(std::string*, const std::string&, const std::vector<unsigned char>&, void*) {
    return false; // the loader never writes
}

uint32_t u32le(const unsigned char* p) {
    return uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24);
}

// GLB layout: 12-byte header (magic, version, length), JSON chunk, optional BIN chunk; every chunk has
// an 8-byte header (length, type). Returns an empty string when the layout is sound.
std::string checkGlb(const std::vector<unsigned char>& bytes) {
    if (bytes.size() < 20)
        return "truncated .glb (" + std::to_string(bytes.size()) + " bytes, header needs 20)";
    if (std::memcmp(bytes.data(), "glTF", 4) != 0) return "not a binary glTF (bad magic)";
    uint32_t version = u32le(&bytes[4]), length = u32le(&bytes[8]);
    if (version != 2) return "unsupported .glb version " + std::to_string(version);
    if (length > bytes.size())
        return "truncated .glb (header says " + std::to_string(length) + " bytes, file has " +
               std::to_string(bytes.size()) + ")";
    uint64_t jsonLength = u32le(&bytes[12]);
    if (u32le(&bytes[16]) != 0x4E4F534Au) return "first .glb chunk is not JSON";
    if (20 + jsonLength > length) return "JSON chunk runs past the end of the .glb";
    uint64_t at = 20 + jsonLength;
    if (at < length) {
        if (at + 8 > length) return "truncated BIN chunk header";
        uint64_t binLength = u32le(&bytes[at]);
        if (at + 8 + binLength > length) return "BIN chunk runs past the end of the .glb";
    }
    return {};
}

} // namespace ml::gltf_guard
