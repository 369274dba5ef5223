#include "bake/bake.h"
#include "bake/bake_tiled.h"
#include "bake/bake_tiled_cpvs.h"
#include "bake/scene_casters.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace ml {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The CPU rasteriser, tile by tile, telling `onFraction` how far it got (DualRasterizer::render without
// the progress would leave a long 16K^2 render silent). `planes`: keep a directional map's enter planes
// (4 B a texel; DAG-MH's planar tree, mh.h), else drop them.
DualDepthMap renderTiled(const CasterTriangles& casters, const LightFrustum& frustum, uint32_t res,
                         uint64_t tileTexels, const std::function<void(double)>& onFraction, bool planes) {
    DualRasterizer raster(casters, frustum, res);
    DualDepthMap map = raster.blankMap();
    if (!planes) std::vector<uint32_t>().swap(map.enterPlane), map.planes.clear();
    const uint32_t rows = uint32_t(std::clamp<uint64_t>(tileTexels / std::max<uint32_t>(res, 1), 1, res));
    for (uint32_t y0 = 0; y0 < res; y0 += rows) {
        const uint32_t y1 = std::min(res, y0 + rows);
        raster.renderRows(y0, y1, map.enter.data() + size_t(y0) * res, map.exit.data() + size_t(y0) * res,
                          map.enterPlane.empty() ? nullptr : map.enterPlane.data() + size_t(y0) * res);
        if (onFraction) onFraction(double(y1) / res);
    }
    return map;
}

} // namespace

// The maps a light bakes: a spot one, a point light six cube faces, a directional light one
// orthographic map over the scene's bounds.
std::vector<LightFrustum> bakeFrustums(const Scene& scene, const Light& l) {
    if (l.type == LightKind::Directional)
        return {directionalLightFrustum(l.direction, scene.boundsMin, scene.boundsMax)};
    return lightFrustums(l);
}

namespace {

// Why a light cannot be baked, or "" when it can.
std::string skipReason(const Scene& scene, const Light& l) {
    if (l.dynamic) return "dynamic light (moves; its shadows come from virtual shadow maps)";
    if (l.type == LightKind::Directional) {
        const glm::vec3 d = l.direction, lo = scene.boundsMin, hi = scene.boundsMax;
        if (!(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z) && glm::length(d) > 1e-6f))
            return "directional light with a zero or non-finite direction";
        if (!(hi.x > lo.x || hi.y > lo.y || hi.z > lo.z) || !std::isfinite(glm::length(hi - lo)))
            return "directional light over empty or non-finite scene bounds";
    } else if (l.type != LightKind::Spot && l.type != LightKind::Point) {
        return "unknown light type";
    }
    for (const LightFrustum& f : bakeFrustums(scene, l)) {
        if (!f.orthographic() && !(f.fov > 0.0f && f.fov < 3.14159f))
            return "cone angle outside (0, 90) degrees";
        if (!(std::isfinite(f.farPlane) && f.farPlane > f.nearPlane))
            return "range not beyond the near plane";
        const float* m = &f.view[0][0];
        for (int i = 0; i < 16; ++i)
            if (!std::isfinite(m[i])) return "position or direction not finite";
    }
    return "";
}

bool sameFrustum(const LightFrustum& a, const LightFrustum& b) {
    return std::memcmp(&a.view[0][0], &b.view[0][0], sizeof(float) * 16) == 0 && a.fov == b.fov &&
           a.nearPlane == b.nearPlane && a.farPlane == b.farPlane && a.orthoHalf == b.orthoHalf &&
           a.orthoHalfY == b.orthoHalfY && a.fitMargin == b.fitMargin;
}

} // namespace

std::string bakeSkipReason(const Scene& scene, const Light& light) {
    return skipReason(scene, light);
}

DualRenderFn cpuDualRenderer(uint64_t tileTexels) {
    return [tileTexels](const CasterTriangles& casters, const LightFrustum& frustum,
                        uint32_t res) -> Result<DualDepthMap> {
        return renderTiled(casters, frustum, res, tileTexels, {}, true);
    };
}

namespace {

// bakeScene with a resolution per light (resOf; 0: not baked) and `res` as the file's resolution.
Result<BakeResult> bakeImpl(const Scene& scene, const SceneSpec& spec, StaticMethod method, uint32_t res,
                            const std::vector<uint32_t>& lightsIn,
                            const std::function<uint32_t(uint32_t)>& resOf, const BakeProgressFn& progress,
                            const DualRenderFn& render, const BakeTiles& tiles) {
    if (!isDepthMethod(method) && method != StaticMethod::CPVS)
        return fail("bake: method '" + std::string(staticMethodName(method)) + "' cannot be baked");
    if (res == 0 || res > kBakeMaxResolution)
        return fail("bake: resolution " + std::to_string(res) + " outside 1.." +
                    std::to_string(kBakeMaxResolution));
    if (res > kBakeWholeMapMax && method == StaticMethod::SM) return fail("bake: " + smPastLimitReason(res));
    if (tiles.tile != 0 && (tiles.tile & (tiles.tile - 1)) != 0)
        return fail("bake: tile side " + std::to_string(tiles.tile) + " is not a power of two");
    if (tiles.tile != 0 && !bakeTiled(method, res, tiles.tile))
        return fail("bake: " + std::string(staticMethodName(method)) +
                    " does not bake in tiles (sm, mh, mmh, dagmh and cpvs do)");
    std::vector<uint32_t> lights = lightsIn;
    std::sort(lights.begin(), lights.end());
    lights.erase(std::unique(lights.begin(), lights.end()), lights.end());
    if (lights.empty()) return fail("bake: no lights selected");
    if (lights.back() >= scene.lights.size())
        return fail("bake: light " + std::to_string(lights.back()) + " is not below the scene's " +
                    std::to_string(scene.lights.size()) + " lights");

    BakeResult out;
    out.file.scene = spec;
    out.file.method = method;
    out.file.resolution = res;
    // (light, face): a spot bakes one map, a point light one per cube face.
    std::vector<std::pair<uint32_t, uint32_t>> work;
    for (uint32_t i : lights) {
        std::string why = skipReason(scene, scene.lights[i]);
        if (why.empty() && resOf(i) == 0) continue; // resolution from need: nothing to cast, not baked
        if (why.empty())
            for (uint32_t face = 0; face < bakeFrustums(scene, scene.lights[i]).size(); ++face)
                work.push_back({i, face});
        else
            out.skipped.push_back({i, why});
    }
    if (work.empty() && out.skipped.empty())
        return fail("bake: none of the " + std::to_string(lights.size()) +
                    " selected lights has a caster in its volume: nothing to bake");
    if (work.empty())
        return fail("bake: none of the " + std::to_string(lights.size()) +
                    " selected lights is a static spot, point or directional light (first skipped: light " +
                    std::to_string(out.skipped[0].light) + ", " + out.skipped[0].reason + ")");
    if (method == StaticMethod::CPVS) {
        // Fail before rendering anything (CPVS needs a power of two in 64..262144, tiled past 16384).
        for (const auto& [li, face] : work)
            if (auto space = makeCpvsSpace(resOf(li), 1.0f, 2.0f); !space)
                return fail("bake: " + space.error());
    }

    const CasterTriangles casters = castersFromScene(scene);
    const auto t0 = Clock::now();
    const uint32_t n = uint32_t(work.size());
    for (uint32_t k = 0; k < n; ++k) {
        const uint32_t li = work[k].first, face = work[k].second;
        auto report = [&](const char* phase, double within) {
            if (progress)
                progress({li, k, n, phase, (k + std::clamp(within, 0.0, 1.0)) / n, secondsSince(t0)});
        };
        const LightFrustum frustum = bakeFrustums(scene, scene.lights[li])[face];
        const uint32_t res = resOf(li);
        LightBakeStats st;
        st.light = li, st.resolution = res;

        if (bakeTiled(method, res, tiles.tile)) {
            // Tile by tile on the CPU rasteriser: the map is never whole (bake_tiled.h).
            report("render", 0.0);
            TiledBakeOptions to;
            to.tile = tiles.tile ? tiles.tile : kBakeDefaultTile, to.maxNodes = tiles.maxNodes;
            to.progress = [&](double f) { report("render", 0.8 * f); };
            auto words = bakeRecordTiled(method, casters, frustum, res, to, st);
            if (!words) return fail("bake: light " + std::to_string(li) + ": tiled: " + words.error());
            st.bytes = words->size() * 4;
            out.renderSeconds += st.renderSeconds, out.encodeSeconds += st.encodeSeconds;
            out.file.records.push_back({li, face, method, res, frustum, std::move(words.value())});
            out.lights.push_back(st);
            report("done", 1.0);
            continue;
        }
        // Render: half of a light's share of the progress; encode: the other half.
        report("render", 0.0);
        auto tr = Clock::now();
        Result<DualDepthMap> map =
            render ? render(casters, frustum, res)
                   : Result<DualDepthMap>(renderTiled(
                         casters, frustum, res, kBakeTileTexels, [&](double f) { report("render", 0.5 * f); },
                         method == StaticMethod::DAGMH));
        if (!map) return fail("bake: light " + std::to_string(li) + ": render: " + map.error());
        // Only DAG-MH's planar tree reads the enter planes (mh.h).
        if (method != StaticMethod::DAGMH) std::vector<uint32_t>().swap(map->enterPlane), map->planes.clear();
        // The projection and rows decide CPVS's slicing and SM's stored rows: from the frustum, whatever
        // renderer made the map.
        map->orthographic = frustum.orthographic(),
        map->rows = frustum.mapRows(res) < res ? frustum.mapRows(res) : 0;
        if (map->resolution != res || map->enter.size() != size_t(res) * res ||
            map->exit.size() != map->enter.size())
            return fail("bake: light " + std::to_string(li) +
                        ": the renderer returned a map of the wrong size");
        st.renderSeconds = secondsSince(tr);
        for (size_t i = 0; i < map->enter.size(); ++i)
            st.coveredTexels += map->enter[i] != kDepthEmpty, st.closedTexels += map->exit[i] > map->enter[i];

        report("encode", 0.5);
        auto te = Clock::now();
        StaticEncodeOptions eo;
        eo.nearPlane = frustum.nearPlane, eo.farPlane = frustum.farPlane;
        eo.progress = [&](float f) { report("encode", 0.5 + 0.5 * double(f)); };
        auto words = encodeStatic(method, map.value(), eo);
        if (!words) return fail("bake: light " + std::to_string(li) + ": encode: " + words.error());
        st.encodeSeconds = secondsSince(te);
        st.bytes = words->size() * 4;
        out.renderSeconds += st.renderSeconds, out.encodeSeconds += st.encodeSeconds;
        out.file.records.push_back({li, face, method, res, frustum, std::move(words.value())});
        out.lights.push_back(st);
        report("done", 1.0);
    }
    return out;
}

} // namespace

Result<BakeResult> bakeScene(const Scene& scene, const SceneSpec& spec, StaticMethod method, uint32_t res,
                             const std::vector<uint32_t>& lights, const BakeProgressFn& progress,
                             const DualRenderFn& render, const BakeTiles& tiles) {
    return bakeImpl(
        scene, spec, method, res, lights, [res](uint32_t) { return res; }, progress, render, tiles);
}

Result<BakeResult> bakeSceneNeed(const Scene& scene, const SceneSpec& spec, StaticMethod method,
                                 const BakeNeed& need, const std::vector<uint32_t>& selected,
                                 const BakeProgressFn& progress, const DualRenderFn& render,
                                 const BakeTiles& tiles) {
    std::vector<uint32_t> lights = selected;
    for (const LightNeed& n : need.lights) {
        if (n.resolution > need.maxRes || (n.resolution != 0 && n.resolution < need.minRes))
            return fail("bake: light " + std::to_string(n.light) + ": resolution " +
                        std::to_string(n.resolution) + " outside " + std::to_string(need.minRes) + ".." +
                        std::to_string(need.maxRes));
        lights.push_back(n.light);
    }
    // Every selected light that can be baked needs an entry (none is left out silently).
    for (uint32_t l : selected)
        if (l < scene.lights.size() && skipReason(scene, scene.lights[l]).empty() &&
            std::none_of(need.lights.begin(), need.lights.end(),
                         [l](const LightNeed& n) { return n.light == l; }))
            return fail("bake: light " + std::to_string(l) + " is selected but has no need entry");
    auto resOf = [&need](uint32_t light) {
        for (const LightNeed& n : need.lights)
            if (n.light == light) return n.resolution;
        return 0u;
    };
    auto out = bakeImpl(scene, spec, method, need.maxRes, lights, resOf, progress, render, tiles);
    if (!out) return out;
    out->file.hasNeed = true;
    out->file.need = need;
    // A light the need gave a resolution but that bakeScene skipped (a dynamic light) keeps no entry
    // claiming a resolution: the file would be refused ("has a resolution but no record").
    auto& ls = out->file.need.lights;
    ls.erase(std::remove_if(ls.begin(), ls.end(),
                            [&](const LightNeed& n) {
                                return std::any_of(out->skipped.begin(), out->skipped.end(),
                                                   [&](const SkippedLight& s) { return s.light == n.light; });
                            }),
             ls.end());
    std::sort(ls.begin(), ls.end(), [](const LightNeed& a, const LightNeed& b) { return a.light < b.light; });
    return out;
}

Result<std::vector<uint32_t>> parseLightSelection(const std::string& text, uint32_t lightCount) {
    std::vector<uint32_t> out;
    if (text == "all") {
        for (uint32_t i = 0; i < lightCount; ++i) out.push_back(i);
        return out;
    }
    auto number = [&](const std::string& s, const std::string& item) -> Result<uint32_t> {
        if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos)
            return fail("--lights: '" + item + "' is not a light index, a range A-B or 'all'");
        uint32_t v = uint32_t(std::strtoul(s.c_str(), nullptr, 10));
        if (v >= lightCount)
            return fail("--lights: light " + s + " out of range (the scene has " +
                        std::to_string(lightCount) + " lights, 0.." +
                        std::to_string(lightCount ? lightCount - 1 : 0) + ")");
        return v;
    };
    if (text.empty()) return fail("--lights: empty selection");
    size_t start = 0;
    while (start <= text.size()) {
        size_t comma = text.find(',', start);
        std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        size_t dash = item.find('-');
        auto lo = number(item.substr(0, dash), item);
        if (!lo) return fail(lo.error());
        uint32_t hi = lo.value();
        if (dash != std::string::npos) {
            auto h = number(item.substr(dash + 1), item);
            if (!h) return fail(h.error());
            if (h.value() < lo.value()) return fail("--lights: range '" + item + "' runs backwards");
            hi = h.value();
        }
        for (uint32_t i = lo.value(); i <= hi; ++i) out.push_back(i);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

Result<VerifyReport> verifyBakeScene(const BakeFile& file, const Scene& scene, const DualRenderFn& render,
                                     const BakeProgressFn& progress, uint32_t tile) {
    VerifyReport rep;
    const CasterTriangles casters = castersFromScene(scene);
    const auto t0 = Clock::now();
    const uint32_t n = uint32_t(file.records.size());
    for (uint32_t k = 0; k < n; ++k) {
        const BakeRecord& rec = file.records[k];
        const std::string where =
            "record " + std::to_string(k) + " (light " + std::to_string(rec.light) + ")";
        auto report = [&](const char* phase, double within) {
            if (progress) progress({rec.light, k, n, phase, (k + within) / n, secondsSince(t0)});
        };
        // The scene must still be the baked one: a changed generator or glTF file would show up as
        // mismatches that are not the codec's fault.
        if (rec.light >= scene.lights.size())
            return fail(where + ": the scene has only " + std::to_string(scene.lights.size()) + " lights");
        const Light& light = scene.lights[rec.light];
        if (std::string why = skipReason(scene, light); !why.empty())
            return fail(where + ": the scene's light is no longer bakeable: " + why);
        if (rec.face >= bakeFrustums(scene, light).size() ||
            !sameFrustum(bakeFrustums(scene, light)[rec.face], rec.frustum))
            return fail(where +
                        ": the light's frustum differs from the baked one (scene changed since the bake?)");

        VerifyLight vl;
        vl.light = rec.light;
        const bool tiledCpvs = rec.method == StaticMethod::CPVS;
        if ((isDepthMethod(rec.method) || tiledCpvs) && (tile != 0 || rec.resolution > kBakeWholeMapMax)) {
            if (file.renderer == BakeRenderer::Gpu && !rec.frustum.orthographic())
                return fail(where + ": tiled verify renders on the CPU rasteriser, and this perspective map "
                                    "was rendered by the Vulkan renderer (verify it without --tile)");
            // Streaming: tile by tile on the CPU rasteriser, bounded memory at any resolution.
            report("check", 0.0);
            const auto verifyTiled = tiledCpvs ? verifyCpvsRecordTiled : verifyRecordTiled;
            if (auto r = verifyTiled(
                    rec, casters, tile ? tile : kBakeDefaultTile, [&](double f) { report("check", f); }, vl,
                    rep.examples, 8);
                !r)
                return fail(where + ": " + r.error());
            rep.checked += vl.checked, rep.mismatches += vl.mismatches, rep.undefined += vl.undefined;
            rep.lights.push_back(vl);
            report("done", 1.0);
            continue;
        }
        report("render", 0.0);
        auto tr = Clock::now();
        Result<DualDepthMap> map = render ? render(casters, rec.frustum, rec.resolution)
                                          : Result<DualDepthMap>(renderTiled(
                                                casters, rec.frustum, rec.resolution, kBakeTileTexels,
                                                [&](double f) { report("render", 0.5 * f); }, false));
        if (!map) return fail(where + ": render: " + map.error());
        map->orthographic = rec.frustum.orthographic();
        map->rows =
            rec.frustum.mapRows(rec.resolution) < rec.resolution ? rec.frustum.mapRows(rec.resolution) : 0;
        if (map->resolution != rec.resolution ||
            map->enter.size() != size_t(rec.resolution) * rec.resolution ||
            map->exit.size() != map->enter.size())
            return fail(where + ": the renderer returned a map of the wrong size");
        vl.renderSeconds = secondsSince(tr);

        report("check", 0.5);
        auto tc = Clock::now();
        const uint32_t* d = rec.data.data();
        const uint32_t res = rec.resolution;
        if (rec.method == StaticMethod::CPVS) {
            CpvsVerifyReport c = verifyCpvs(d, map.value());
            vl.checked = c.checked, vl.undefined = c.undefined, vl.mismatches = c.mismatches;
            if (c.mismatches && rep.examples.size() < 8)
                rep.examples.push_back(where + ": " + std::to_string(c.mismatches) + " voxels disagree");
        } else {
            for (uint32_t y = 0; y < res; ++y) {
                for (uint32_t x = 0; x < res; ++x) {
                    const size_t i = size_t(y) * res + x;
                    const uint32_t e = map->enter[i], f = std::max(e, map->exit[i]);
                    const uint32_t v = lookupStaticDepth(rec.method, d, 0, x, y);
                    const bool ok = e == kDepthEmpty ? v == kDepthEmpty : (e <= v && v <= f);
                    if (!ok && ++vl.mismatches && rep.examples.size() < 8)
                        rep.examples.push_back(where + ": texel (" + std::to_string(x) + ", " +
                                               std::to_string(y) + ") decodes " + std::to_string(v) +
                                               " outside [" + std::to_string(e) + ", " + std::to_string(f) +
                                               "]");
                }
                if ((y & 255) == 255) report("check", 0.5 + 0.5 * double(y + 1) / res);
            }
            vl.checked = uint64_t(res) * res;
        }
        if (rec.frustum.fitted()) {
            uint32_t lo = kDepthEmpty, hi = 0;
            for (uint32_t e : map->enter)
                if (e != kDepthEmpty) lo = std::min(lo, e), hi = std::max(hi, e);
            const double nz = rec.frustum.nearPlane, fz = rec.frustum.farPlane, n = rec.resolution;
            auto slice = [&](uint32_t q) {
                return std::clamp(std::floor((dequantizeDepth(q, rec.frustum.farPlane) - nz) / (fz - nz) * n),
                                  0.0, n - 1);
            };
            vl.casterSlices = lo <= hi ? (slice(hi) - slice(lo) + 1) / n : 0.0;
        }
        vl.checkSeconds = secondsSince(tc);
        rep.checked += vl.checked, rep.mismatches += vl.mismatches, rep.undefined += vl.undefined;
        rep.lights.push_back(vl);
        report("done", 1.0);
    }
    return rep;
}

Result<SceneModifiers> parseSceneModifiers(const std::string& scene) {
    SceneModifiers m;
    size_t bar = scene.find('|');
    m.base = scene.substr(0, bar);
    while (bar != std::string::npos) {
        size_t next = scene.find('|', bar + 1);
        std::string item =
            scene.substr(bar + 1, next == std::string::npos ? std::string::npos : next - bar - 1);
        bar = next;
        size_t eq = item.find('=');
        std::string key = item.substr(0, eq);
        std::vector<float> v;
        if (eq != std::string::npos) {
            std::string rest = item.substr(eq + 1);
            size_t pos = 0;
            while (pos <= rest.size()) {
                size_t comma = rest.find(',', pos);
                std::string num =
                    rest.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
                char* end = nullptr;
                float f = std::strtof(num.c_str(), &end);
                if (num.empty() || *end != '\0' || !std::isfinite(f))
                    return fail("scene modifier '" + item + "': '" + num + "' is not a finite number");
                v.push_back(f);
                if (comma == std::string::npos) break;
                pos = comma + 1;
            }
        }
        if (key == "bounds" && v.size() == 6) {
            m.bounds = true;
            m.boundsMin = {v[0], v[1], v[2]};
            m.boundsMax = {v[3], v[4], v[5]};
            if (!(m.boundsMax.x >= m.boundsMin.x && m.boundsMax.y >= m.boundsMin.y &&
                  m.boundsMax.z >= m.boundsMin.z))
                return fail("scene modifier '" + item + "': max below min");
        } else if (key == "light-dir" && v.size() == 3) {
            glm::vec3 d(v[0], v[1], v[2]);
            if (!(glm::length(d) > 1e-6f)) return fail("scene modifier '" + item + "': zero direction");
            m.lightDirs.push_back(d);
        } else {
            return fail("scene modifier '" + item + "': expected bounds=6 numbers or light-dir=3 numbers");
        }
    }
    return m;
}

std::string sceneModifierString(const SceneModifiers& m) {
    std::string s = m.base;
    auto num = [](float f) {
        char b[32];
        std::snprintf(b, sizeof(b), "%.9g", double(f));
        return std::string(b);
    };
    if (m.bounds)
        s += "|bounds=" + num(m.boundsMin.x) + "," + num(m.boundsMin.y) + "," + num(m.boundsMin.z) + "," +
             num(m.boundsMax.x) + "," + num(m.boundsMax.y) + "," + num(m.boundsMax.z);
    for (glm::vec3 d : m.lightDirs) s += "|light-dir=" + num(d.x) + "," + num(d.y) + "," + num(d.z);
    return s;
}

void applySceneModifiers(Scene& scene, const SceneModifiers& m) {
    if (m.bounds) scene.boundsMin = m.boundsMin, scene.boundsMax = m.boundsMax;
    for (glm::vec3 d : m.lightDirs) {
        Light l;
        l.type = LightKind::Directional;
        l.direction = glm::normalize(d);
        l.position = (scene.boundsMin + scene.boundsMax) * 0.5f; // unused by directional lights
        scene.lights.push_back(l);
    }
}

Result<Scene> loadBakeScene(const SceneSpec& spec, const LoadOptions& options) {
    auto m = parseSceneModifiers(spec.scene);
    if (!m) return fail(m.error());
    const uint32_t extra = uint32_t(m->lightDirs.size());
    if (spec.lights <= extra)
        return fail("scene '" + spec.scene + "': light count below its appended lights");
    auto scene = loadScene(m->base, spec.lights - extra, spec.seed, options);
    if (!scene) return scene;
    applySceneModifiers(scene.value(), m.value());
    return scene;
}

Result<VerifyReport> verifyBake(const BakeFile& file, const DualRenderFn& render,
                                const BakeProgressFn& progress) {
    auto scene = loadBakeScene(file.scene);
    if (!scene) return fail("cannot re-create the baked scene: " + scene.error());
    return verifyBakeScene(file, scene.value(), render, progress);
}

} // namespace ml
