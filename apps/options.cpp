#include "apps/options.h"
#include "shadows/static/bake.h"

#include <cmath>
#include <cstdlib>

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

Result<std::vector<uint32_t>> uintList(const std::string& flag, const std::string& text, uint32_t lo,
                                       uint32_t hi) {
    auto items = splitList(flag, text);
    if (!items) return fail(items.error());
    std::vector<uint32_t> out;
    for (const std::string& item : items.value()) {
        auto v = cli::parseUint(flag, item, lo, hi);
        if (!v) return fail(v.error());
        out.push_back(v.value());
    }
    return out;
}

Result<std::vector<StaticMethod>> methodList(const std::string& flag, const std::string& text) {
    auto items = splitList(flag, text);
    if (!items) return fail(items.error());
    std::vector<StaticMethod> out;
    for (const std::string& item : items.value()) {
        auto m = parseStaticMethod(item);
        if (!m) return fail(flag + ": " + m.error());
        if (m.value() == StaticMethod::None) return fail(flag + ": method none");
        out.push_back(m.value());
    }
    return out;
}

Result<std::vector<CullingMode>> cullingList(const std::string& flag, const std::string& text) {
    auto items = splitList(flag, text);
    if (!items) return fail(items.error());
    std::vector<CullingMode> out;
    for (const std::string& item : items.value()) {
        auto m = parseCulling(item);
        if (!m) return fail(flag + ": " + m.error());
        out.push_back(m.value());
    }
    return out;
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
