#include "apps/options.h"
#include "bake/bake.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>

namespace ml::opts {

Result<uint32_t> seed(const cli::Args& args) {
    return cli::parseUint("--seed", args.get("--seed", "1"), 0, 0xFFFFFFFFu);
}

Result<Scene> scene(const cli::Args& args) {
    auto s = seed(args);
    if (!s) return fail(s.error());
    return Scene{args.get("--scene", "night-city"), s.value(), args.has("--allow-outside-scene-dir")};
}

Result<View> view(const cli::Args& args, const ViewDefaults& d) {
    auto frames =
        cli::parseUint("--frames", args.get("--frames", std::to_string(d.frames)), d.minFrames, d.maxFrames);
    if (!frames) return fail(frames.error());
    auto size = cli::parseSize("--size", args.get("--size", d.size));
    if (!size) return fail(size.error());
    return View{frames.value(), size->first, size->second};
}

Result<Need> need(const cli::Args& args, const std::string& defaultSize) {
    auto size = cli::parseSize("--need-size", args.get("--need-size", defaultSize));
    auto minRes = cli::parseUint("--need-min", args.get("--need-min", "64"), 1, kBakeMaxResolution);
    auto samples = cli::parseUint("--need-samples", args.get("--need-samples", "120"), 1, 100000);
    auto seconds = cli::parseUint("--need-seconds", args.get("--need-seconds", "60"), 1, 86400);
    for (const std::string* e : {&size.error(), &minRes.error(), &samples.error(), &seconds.error()})
        if (!e->empty()) return fail(*e);
    return Need{size->first, size->second, minRes.value(), samples.value(), seconds.value()};
}

Result<void> checkNeedMin(uint32_t minRes) {
    if ((minRes & (minRes - 1)) != 0)
        return fail("--need-min: " + std::to_string(minRes) + " is not a power of two");
    return {};
}

Result<std::vector<std::string>> splitList(const std::string& flag, const std::string& text) {
    if (text.empty()) return fail(flag + ": empty list");
    std::vector<std::string> items;
    size_t at = 0;
    for (;;) {
        const size_t comma = text.find(',', at);
        items.push_back(text.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
        if (items.back().empty()) return fail(flag + ": empty item in '" + text + "'");
        if (comma == std::string::npos) return items;
        at = comma + 1;
    }
}

namespace {
// Each item of the list through `parse` (a Result per item); the first error ends it.
template <class T, class Parse>
Result<std::vector<T>> listOf(const std::string& flag, const std::string& text, const Parse& parse) {
    auto items = splitList(flag, text);
    if (!items) return fail(items.error());
    std::vector<T> out;
    for (const std::string& item : items.value()) {
        Result<T> v = parse(item);
        if (!v) return fail(v.error());
        out.push_back(v.value());
    }
    return out;
}
} // namespace

Result<std::vector<uint32_t>> uintList(const std::string& flag, const std::string& text, uint32_t lo,
                                       uint32_t hi) {
    return listOf<uint32_t>(flag, text,
                            [&](const std::string& item) { return cli::parseUint(flag, item, lo, hi); });
}

Result<std::vector<StaticMethod>> methodList(const std::string& flag, const std::string& text) {
    return listOf<StaticMethod>(flag, text, [&](const std::string& item) -> Result<StaticMethod> {
        auto m = parseStaticMethod(item);
        if (!m) return fail(flag + ": " + m.error());
        if (m.value() == StaticMethod::None) return fail(flag + ": method none");
        return m;
    });
}

Result<std::vector<CullingMode>> cullingList(const std::string& flag, const std::string& text) {
    return listOf<CullingMode>(flag, text, [&](const std::string& item) -> Result<CullingMode> {
        auto m = parseCulling(item);
        if (!m) return fail(flag + ": " + m.error());
        return m;
    });
}

uint64_t machineMemory() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : uint64_t(4) << 30;
}

Result<uint64_t> maxMemory(const cli::Args& args) {
    const uint64_t half = machineMemory() / 2;
    if (!args.has("--max-memory")) return half;
    auto mib = cli::parseUint("--max-memory", args.get("--max-memory", ""), 64, 1u << 30);
    if (!mib) return fail(mib.error() + " (MiB)");
    return uint64_t(mib.value()) << 20;
}

Result<void> checkMemory(const char* command, uint64_t estimate, uint64_t limit, const std::string& what) {
    const uint64_t m = 1u << 20;
    if (estimate > limit)
        return fail("estimated peak memory " + std::to_string((estimate + m - 1) / m) + " MiB (" + what +
                    ") exceeds the limit " + std::to_string(limit / m) +
                    " MiB (--max-memory MIB raises it; the default is half of this machine's " +
                    std::to_string(machineMemory() / m) + " MiB)");
    std::fprintf(stderr, "manylights %s: estimated peak memory %llu MiB (%s), limit %llu MiB\n", command,
                 (unsigned long long)((estimate + m - 1) / m), what.c_str(), (unsigned long long)(limit / m));
    return {};
}

Result<float> number(const std::string& flag, const std::string& text, float lo, float hi) {
    char* end = nullptr;
    const double d = std::strtod(text.c_str(), &end);
    if (text.empty() || *end || !std::isfinite(d) || d < lo || d > hi)
        return fail(flag + ": '" + text + "' is not a number in [" + std::to_string(lo) + ", " +
                    std::to_string(hi) + "]");
    return float(d);
}

} // namespace ml::opts
