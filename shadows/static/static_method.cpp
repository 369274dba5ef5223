#include "shadows/static/static_method.h"

namespace ml {

const char* staticMethodName(StaticMethod m) {
    switch (m) {
    case StaticMethod::None:
        return "none";
    case StaticMethod::SM:
        return "sm";
    case StaticMethod::MH:
        return "mh";
    case StaticMethod::MMH:
        return "mmh";
    case StaticMethod::DAGMH:
        return "dagmh";
    case StaticMethod::CPVS:
        return "cpvs";
    }
    return "?";
}

Result<StaticMethod> parseStaticMethod(const std::string& name) {
    for (StaticMethod m : {StaticMethod::None, StaticMethod::SM, StaticMethod::MH, StaticMethod::MMH,
                           StaticMethod::DAGMH, StaticMethod::CPVS})
        if (name == staticMethodName(m)) return m;
    return fail("unknown static method '" + name + "' (sm, mh, mmh, dagmh, cpvs or none)");
}

Result<std::vector<uint32_t>> encodeStatic(StaticMethod method, const DualDepthMap& map,
                                           const StaticEncodeOptions& options) {
    switch (method) {
    case StaticMethod::SM:
        return encodeSM(map);
    case StaticMethod::MH:
        return encodeMH(map);
    case StaticMethod::MMH:
        return encodeMMH(map);
    case StaticMethod::DAGMH:
        return encodeDAGMH(map);
    case StaticMethod::CPVS: {
        CpvsParams p;
        p.resolution = map.resolution;
        p.nearPlane = options.nearPlane;
        p.farPlane = options.farPlane;
        // Directional (orthographic) maps: equal slices over the box's slab; others eq. 1.
        p.slicing = map.orthographic ? CpvsSlicing::Linear : CpvsSlicing::Log;
        p.progress = options.progress;
        auto bake = bakeCpvs(map, p);
        if (!bake) return fail(bake.error());
        if (options.cpvsStats) *options.cpvsStats = bake->stats;
        return std::move(bake->data);
    }
    case StaticMethod::None:
        break;
    }
    return fail("encodeStatic: method 'none' has no encoding");
}

Result<void> validateStatic(StaticMethod method, const uint32_t* data, size_t words) {
    switch (method) {
    case StaticMethod::SM:
        return validateSM(data, words);
    case StaticMethod::MH:
        return validateMH(data, words);
    case StaticMethod::MMH:
        return validateMMH(data, words);
    case StaticMethod::DAGMH:
        return validateDAGMH(data, words);
    case StaticMethod::CPVS:
        return validateCpvs(data, words);
    case StaticMethod::None:
        break;
    }
    return fail("validateStatic: unknown method " + std::to_string(uint32_t(method)));
}

stat::ByteBreakdown breakdownStatic(StaticMethod method, const uint32_t* data, size_t words) {
    switch (method) {
    case StaticMethod::SM:
        return breakdownSM(data, words);
    case StaticMethod::MH:
        return breakdownMH(data, words);
    case StaticMethod::MMH:
        return breakdownMMH(data, words);
    case StaticMethod::DAGMH:
        return breakdownDAGMH(data, words);
    case StaticMethod::CPVS: {
        CpvsBytes c = cpvsBytes(data);
        stat::ByteBreakdown b;
        b.header = c.header + c.thresholds;
        b.skipList = c.grid;
        b.nodes = c.innerNodes;
        b.values = c.leafMasks;
        return b;
    }
    case StaticMethod::None:
        break;
    }
    return {};
}

// Word 2 of every format's header is its resolution (sm.h, mh.h, dagmh.h, docs/cpvs-layout.md).
uint32_t staticResolution(StaticMethod, const uint32_t* data) {
    return data[2];
}

uint32_t lookupStaticDepth(StaticMethod method, const uint32_t* data, uint32_t base, uint32_t x, uint32_t y) {
    switch (method) {
    case StaticMethod::SM:
        return smLookup(data, base, x, y);
    case StaticMethod::MH:
        return mhLookup(data, base, x, y);
    case StaticMethod::MMH:
        return mmhLookup(data, base, x, y);
    case StaticMethod::DAGMH:
        return dagmhLookup(data, base, x, y);
    default:
        return kDepthEmpty;
    }
}

} // namespace ml
