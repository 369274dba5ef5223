#include "apps/cli.h"
#include "manylights/manylights.h"
#include "io/safe_io.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace ml::cli {

Result<Args> parse(int argc, char** argv, int first, const std::set<std::string>& valued,
                   const std::set<std::string>& switches) {
    Args a;
    for (int i = first; i < argc; ++i) {
        std::string s = argv[i];
        if (s == "--help" || s == "-h") {
            a.help = true;
            continue;
        }
        // A flag given twice would silently keep one of its values: refused.
        if ((valued.count(s) || switches.count(s)) && a.has(s)) return fail(s + ": given twice");
        if (valued.count(s)) {
            if (i + 1 >= argc) return fail(s + ": missing value");
            // "--culling --frames 1" would take "--frames" as the value and then stumble on "1".
            const std::string v = argv[i + 1];
            if (valued.count(v) || switches.count(v) || v == "--help")
                return fail(s + ": missing value (the next argument is the flag " + v + ")");
            // No value starts with "--" (paths and numbers do not; a negative number has one dash).
            if (v.rfind("--", 0) == 0)
                return fail(s + ": missing value (the next argument, '" + v + "', is a flag)");
            a.values[s] = argv[++i];
        } else if (switches.count(s)) {
            a.switches.insert(s);
        } else {
            return fail("unknown argument '" + s + "' (see --help)");
        }
    }
    return a;
}

Result<Args> parse(int argc, char** argv, int first, std::initializer_list<Flags> groups) {
    Flags all;
    for (const Flags& g : groups)
        for (const auto* names : {&g.valued, &g.switches})
            for (const std::string& name : *names)
                if (all.valued.count(name) || all.switches.count(name))
                    return fail(name + ": defined by two option groups");
                else
                    (names == &g.valued ? all.valued : all.switches).insert(name);
    return parse(argc, argv, first, all.valued, all.switches);
}

Result<uint32_t> parseUint(const std::string& flag, const std::string& text, uint32_t lo, uint32_t hi) {
    char* end = nullptr;
    errno = 0;
    long long v = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end || errno || v < lo || v > hi)
        return fail(flag + ": '" + text + "' is not a whole number in " + std::to_string(lo) + ".." +
                    std::to_string(hi));
    return uint32_t(v);
}

Result<std::pair<uint32_t, uint32_t>> parseSize(const std::string& flag, const std::string& text) {
    auto x = text.find('x');
    if (x == std::string::npos) return fail(flag + ": '" + text + "' is not WIDTHxHEIGHT");
    auto w = parseUint(flag + " width", text.substr(0, x), 1, 16384);
    if (!w) return fail(w.error());
    auto h = parseUint(flag + " height", text.substr(x + 1), 1, 16384);
    if (!h) return fail(h.error());
    return std::make_pair(w.value(), h.value());
}

Result<std::array<float, 6>> parseCamera(const std::string& flag, const std::string& text) {
    // strtod per field (not sscanf %f): the whole field must be a number, and "nan", "inf" or 1e39
    // (inf as a float) are refused with the field named.
    std::array<float, 6> v{};
    const char* names[6] = {"X", "Y", "Z", "TX", "TY", "TZ"};
    const std::string form = flag + ": '" + text + "' is not X,Y,Z,TX,TY,TZ";
    size_t at = 0;
    for (int i = 0; i < 6; ++i) {
        const size_t comma = i < 5 ? text.find(',', at) : text.size();
        if (comma == std::string::npos) return fail(form);
        const std::string field = text.substr(at, comma - at);
        char* end = nullptr;
        errno = 0;
        const double d = std::strtod(field.c_str(), &end);
        if (field.empty() || *end) return fail(form);
        if (!std::isfinite(d) || std::abs(d) > kMaxCameraCoordinate)
            return fail(flag + ": " + names[i] + " = '" + field + "' is not a finite number within +-" +
                        std::to_string(int(kMaxCameraCoordinate)));
        v[size_t(i)] = float(d);
        at = comma + 1;
    }
    CameraDesc c;
    c.position = {v[0], v[1], v[2]};
    c.target = {v[3], v[4], v[5]};
    if (auto r = validateCamera(c); !r) return fail(flag + ": " + r.error().substr(sizeof("camera: ") - 1));
    return v;
}

Result<void> makeDirectory(const std::string& path) {
    std::error_code ec;
    std::filesystem::create_directories(path, ec);
    if (ec) return fail(path + ": cannot create directory: " + ec.message());
    return {};
}

Result<void> checkOutputFile(const std::string& flag, const std::string& path) {
    if (path.empty()) return fail(flag + ": empty path");
    const size_t slash = path.find_last_of('/');
    if (slash != std::string::npos && slash > 0)
        if (auto r = makeDirectory(path.substr(0, slash)); !r) return fail(flag + ": " + r.error());
    if (auto r = io::checkReplaceable(path); !r) return fail(flag + ": " + r.error());
    return {};
}

Result<void> checkOutputDirectory(const std::string& flag, const std::string& path) {
    if (path.empty()) return fail(flag + ": empty path");
    if (auto r = makeDirectory(path); !r) return fail(flag + ": " + r.error());
    return {};
}

} // namespace ml::cli
