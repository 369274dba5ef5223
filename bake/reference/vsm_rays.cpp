#include "bake/reference/vsm_rays.h"

#include "shaders/shared/light_math.h"

#include <algorithm>
#include <cmath>

namespace ml {

const char* vsmRayClassName(VsmRayClass c) {
    switch (c) {
    case VsmRayClass::Fallback:
        return "fallback";
    case VsmRayClass::Bias:
        return "bias";
    case VsmRayClass::Seam:
        return "seam";
    case VsmRayClass::Resolution:
        return "resolution";
    default:
        return "other";
    }
}

void VsmRayCounts::merge(const VsmRayCounts& o) {
    pairs += o.pairs, raysLit += o.raysLit, vsmLit += o.vsmLit, mismatches += o.mismatches;
    vsmShadowsLit += o.vsmShadowsLit, vsmLightsShadow += o.vsmLightsShadow;
    for (uint32_t i = 0; i < kVsmRayClassCount; ++i) byClass[i] += o.byClass[i];
    directional += o.directional, missing += o.missing, outsideCone += o.outsideCone;
    backFacing += o.backFacing, unknownLight += o.unknownLight, probeDisagrees += o.probeDisagrees;
    fallbackPairs += o.fallbackPairs, probeOverflow += o.probeOverflow;
}

Result<VsmRayFrame> readVsmRayFrame(Module& module) {
    VsmRayFrame f;
    f.probes = diag::readVsmProbes(module, &f.probeOverflow);
    f.pages = diag::readVsmPageState(module);
    f.maps = diag::vsmMaps(module);
    f.constants = diag::lastFrame(module);
    if (auto r = diag::readGBuffer(module, f.depth, f.normal); !r) return fail(r.error());
    return f;
}

namespace {

uint64_t pairKey(uint32_t pixel, uint32_t light) {
    return (uint64_t(pixel) << 32) | light;
}

// Where each (pixel, light) lookup ended: map and mip, for the seam test.
using Places = std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>>;

// A probe that passed the filters, waiting for its rays.
struct Pending {
    const diag::VsmProbe* probe = nullptr;
    glm::vec3 p{0.0f}, n{0.0f};
    bool vsm = false;
};

// The texel side in metres of `map` at `mip` for a receiver at light-view depth z (vsmLocate's
// texelWorld: perspective maps only).
float texelWorld(const diag::VsmMap& map, uint32_t resolution, uint32_t mip, float z) {
    return 2.0f * z * std::tan(map.frustum.fov * 0.5f) / float(std::max(resolution >> mip, 1u));
}

VsmRayClass classify(const VsmRayFrame& f, const RayReference& rays, const Places& places,
                     const VsmRayOptions& o, const Light& L, uint32_t width, uint32_t height,
                     const Pending& q, bool truth) {
    const diag::VsmProbe& pr = *q.probe;
    if (pr.status == diag::VsmProbeStatus::Fallback) return VsmRayClass::Fallback;
    const diag::VsmMap& map = f.maps[pr.map];
    const float z = -glm::vec3(map.frustum.view * glm::vec4(q.p, 1.0f)).z;
    const float texel = texelWorld(map, o.resolution, pr.mip, z);
    const float band = (o.depthBias + o.normalBias + 1.0f) * texel + o.rayBias;
    const glm::vec3 nl = glm::dot(q.n, L.position - q.p) < 0.0f ? -q.n : q.n; // the rays' rule
    if (!q.vsm && pr.depth != 0xFFFFFFFFu) {
        // The VSM shadows: the depth it read, back in metres (vsmQuantize is linear over [0, far]). The
        // receiver's own surface spans tan(angle to the light) texels of depth across one texel, so
        // a surface that steep shadows itself from that far in front (acne at grazing light).
        const double occluder = double(pr.depth) / 4294967040.0 * double(map.frustum.farPlane);
        const float c = std::clamp(glm::dot(nl, glm::normalize(L.position - q.p)), 1e-3f, 1.0f);
        const float slope = std::sqrt(std::max(1.0f - c * c, 0.0f)) / c;
        if (double(z) - occluder < double(band + slope * texel)) return VsmRayClass::Bias;
    } else if (q.vsm && !truth) {
        const glm::vec3 start = q.p + nl * 1e-4f, toLight = L.position - start;
        const float dist = glm::length(toLight);
        if (dist > 0.0f && rays.firstHit(start, toLight / dist, 0.0f, std::min(band, dist)).hit)
            return VsmRayClass::Bias;
    }
    const diag::VsmPageState& st = *f.pages;
    const int res = int(o.resolution >> pr.mip), tx = int(pr.x), ty = int(pr.y);
    bool seam = false, resolution = false;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int x = tx + dx, y = ty + dy;
            if ((!dx && !dy) || x < 0 || y < 0 || x >= res || y >= res) continue;
            uint32_t centre = 0;
            const int lit = diag::vsmKernelLit(st, pr.map, pr.mip, x, y, pr.receiverDepth, 0, centre);
            if (lit < 0)
                seam = true;
            else if ((lit > 0) != q.vsm)
                resolution = true;
        }
    const uint32_t px = pr.pixel % width, py = pr.pixel / width;
    for (auto [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
        const int x = int(px) + dx, y = int(py) + dy;
        if (x < 0 || y < 0 || x >= int(width) || y >= int(height)) continue;
        auto it = places.find(pairKey(uint32_t(y) * width + uint32_t(x), pr.light));
        if (it != places.end() && it->second != std::make_pair(pr.map, pr.mip)) seam = true;
    }
    if (seam) return VsmRayClass::Seam;
    if (resolution) return VsmRayClass::Resolution;
    return VsmRayClass::Other;
}

} // namespace

void measureVsmRays(const VsmRayFrame& f, const Scene& scene, const RayReference& rays,
                    const std::unordered_map<uint32_t, uint32_t>& sceneLight, const VsmRayOptions& o,
                    VsmRayCounts& c, std::vector<VsmRayPair>* out) {
    c.probeOverflow += f.probeOverflow;
    const uint32_t width = f.constants.size.x, height = f.constants.size.y;
    Places places;
    for (const diag::VsmProbe& p : f.probes)
        if (p.status != diag::VsmProbeStatus::Missing)
            places.emplace(pairKey(p.pixel, p.light), std::make_pair(p.map, p.mip));
    // Per scene light, the receivers to trace (visibleBatch takes one light position at a time).
    std::unordered_map<uint32_t, std::vector<Pending>> batches;
    for (const diag::VsmProbe& p : f.probes) {
        if (p.status == diag::VsmProbeStatus::Missing) {
            ++c.missing;
            continue;
        }
        if (p.map >= f.maps.size() || f.maps[p.map].orthographic) {
            ++c.directional;
            continue;
        }
        auto sl = sceneLight.find(p.light);
        if (sl == sceneLight.end() || sl->second >= scene.lights.size()) {
            ++c.unknownLight;
            continue;
        }
        const Light& L = scene.lights[sl->second];
        const uint32_t px = p.pixel % width, py = p.pixel / width;
        Pending q;
        q.probe = &p;
        q.p = gpu::worldFromPixel(px, py, f.depth[p.pixel], f.constants.invViewProj, f.constants.size);
        const glm::vec3 n = f.normal[p.pixel];
        const float len = glm::length(n);
        q.n = len > 0.0f ? n / len : glm::vec3(0, 1, 0);
        if (!inLightCone(L, q.p)) {
            ++c.outsideCone;
            continue;
        }
        if (!(glm::dot(q.n, L.position - q.p) > 0.0f)) {
            ++c.backFacing; // unlit by N.L whatever the shadow says
            continue;
        }
        uint32_t centre = 0;
        const int lit =
            diag::vsmKernelLit(*f.pages, p.map, p.mip, int(p.x), int(p.y), p.receiverDepth, 0, centre);
        const bool needsPage = diag::vsmTexelNeedsPage(*f.pages, p.map, p.mip, int(p.x), int(p.y));
        const bool agrees =
            lit >= 0 &&
            (p.status == diag::VsmProbeStatus::NoCaster ? !needsPage : needsPage && centre == p.depth);
        if (!agrees) {
            ++c.probeDisagrees; // the CPU twin does not reproduce the probe: nothing to judge
            continue;
        }
        q.vsm = lit > 0;
        batches[sl->second].push_back(q);
    }
    for (auto& [light, batch] : batches) {
        const Light& L = scene.lights[light];
        std::vector<glm::vec3> ps, ns;
        for (const Pending& q : batch) ps.push_back(q.p), ns.push_back(q.n);
        std::vector<uint8_t> truth(ps.size());
        rays.visibleBatch(ps.data(), ns.data(), ps.size(), L.position, o.rayBias, truth.data());
        for (size_t i = 0; i < batch.size(); ++i) {
            const Pending& q = batch[i];
            const bool t = truth[i] != 0;
            ++c.pairs;
            c.raysLit += t, c.vsmLit += q.vsm;
            c.fallbackPairs += q.probe->status == diag::VsmProbeStatus::Fallback;
            VsmRayPair pair{q.probe->pixel, light, q.p, q.n, t, q.vsm, VsmRayClass::Other};
            if (t != q.vsm) {
                ++c.mismatches;
                c.vsmShadowsLit += t, c.vsmLightsShadow += !t;
                pair.cause = classify(f, rays, places, o, L, width, height, q, t);
                ++c.byClass[uint32_t(pair.cause)];
            }
            if (out) out->push_back(pair);
        }
    }
}

} // namespace ml
