#include "bake/bake_shard.h"
#include "bake/scene_casters.h"

#include "io/safe_io.h"

#include "bake/bake.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

namespace ml {

using namespace partfmt;

namespace {

uint32_t padWords(size_t bytes) {
    return uint32_t((bytes + 3) / 4);
}
uint64_t join(uint32_t lo, uint32_t hi) {
    return uint64_t(lo) | uint64_t(hi) << 32;
}

bool strictlyIncreasing(const std::vector<uint32_t>& v) {
    for (size_t i = 1; i < v.size(); ++i)
        if (v[i] <= v[i - 1]) return false;
    return true;
}

// "3, 7, 12" (at most 8 ids, then "and N more"): the lights an error names.
std::string lightList(const std::vector<uint32_t>& lights) {
    std::string s;
    for (size_t i = 0; i < lights.size() && i < 8; ++i) s += (i ? ", " : "") + std::to_string(lights[i]);
    if (lights.size() > 8) s += " and " + std::to_string(lights.size() - 8) + " more";
    return s;
}

std::string hex64(uint64_t v) {
    char buf[24];
    std::snprintf(buf, sizeof(buf), "%016llx", (unsigned long long)v);
    return buf;
}

std::string shardName(ShardId id) {
    return std::to_string(id.index) + "/" + std::to_string(id.count);
}

} // namespace

Result<ShardId> parseShard(const std::string& text) {
    auto bad = [&] {
        return fail("--shard: '" + text + "' is not I/N with 0 <= I < N <= " + std::to_string(kMaxShards));
    };
    const size_t slash = text.find('/');
    if (slash == std::string::npos) return bad();
    auto number = [](const std::string& s, uint32_t& v) {
        if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos) return false;
        v = uint32_t(std::stoul(s));
        return true;
    };
    ShardId id;
    if (!number(text.substr(0, slash), id.index) || !number(text.substr(slash + 1), id.count)) return bad();
    if (id.count == 0 || id.count > kMaxShards || id.index >= id.count) return bad();
    return id;
}

uint64_t bakeCostEstimate(const Scene& scene, const Light& light, uint32_t resolution) {
    if (!bakeSkipReason(scene, light).empty()) return 0;
    return uint64_t(bakeFrustums(scene, light).size()) * resolution * resolution;
}

std::vector<std::vector<uint32_t>> splitShards(const std::vector<std::pair<uint32_t, uint64_t>>& costs,
                                               uint32_t count) {
    std::vector<std::pair<uint32_t, uint64_t>> order = costs;
    std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
        return a.second != b.second ? a.second > b.second : a.first < b.first;
    });
    std::vector<std::vector<uint32_t>> shards(std::max(count, 1u));
    std::vector<uint64_t> load(shards.size(), 0);
    for (const auto& [light, cost] : order) {
        // The least loaded shard, the lower index on a tie (min_element returns the first minimum).
        const size_t s = size_t(std::min_element(load.begin(), load.end()) - load.begin());
        shards[s].push_back(light);
        load[s] += cost;
    }
    for (auto& s : shards) std::sort(s.begin(), s.end());
    return shards;
}

std::vector<uint32_t> shardLights(const Scene& scene, const std::vector<uint32_t>& selected, uint32_t res,
                                  ShardId id) {
    std::vector<std::pair<uint32_t, uint64_t>> costs;
    for (uint32_t l : selected)
        costs.push_back({l, l < scene.lights.size() ? bakeCostEstimate(scene, scene.lights[l], res) : 0});
    return splitShards(costs, id.count)[id.index];
}

uint64_t fnv1a64(const void* data, size_t bytes, uint64_t h) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    return h;
}

uint64_t sceneFingerprint(const Scene& scene) {
    uint64_t h = fnv1a64(nullptr, 0);
    auto word = [&](uint64_t v) { h = fnv1a64(&v, sizeof(v), h); };
    const CasterTriangles casters = castersFromScene(scene);
    word(casters.positions.size());
    h = fnv1a64(casters.positions.data(), casters.positions.size() * sizeof(glm::vec3), h);
    h = fnv1a64(casters.closed.data(), casters.closed.size(), h);
    word(scene.lights.size());
    for (const Light& l : scene.lights) {
        word(uint64_t(l.type)), word(l.dynamic ? 1 : 0);
        const std::vector<LightFrustum> fs = lightFrustums(l);
        word(fs.size());
        for (const LightFrustum& f : fs) {
            h = fnv1a64(&f.view[0][0], sizeof(float) * 16, h);
            h = fnv1a64(&f.fov, sizeof(float), h), h = fnv1a64(&f.nearPlane, sizeof(float), h);
            h = fnv1a64(&f.farPlane, sizeof(float), h);
        }
    }
    return h;
}

Result<std::vector<uint32_t>> serializeBakePart(const BakePart& p) {
    if (p.shard.count == 0 || p.shard.count > kMaxShards || p.shard.index >= p.shard.count)
        return fail("bake part: shard " + shardName(p.shard) + " out of range");
    if (p.selected.empty() || p.selected.size() > kMaxLights || !strictlyIncreasing(p.selected) ||
        !strictlyIncreasing(p.own) ||
        !std::includes(p.selected.begin(), p.selected.end(), p.own.begin(), p.own.end()))
        return fail("bake part: the light lists are not sorted, unique and nested");
    if (p.device.empty() || p.device.size() > kMaxDeviceBytes || p.device.find('\0') != std::string::npos)
        return fail("bake part: device string must be 1.." + std::to_string(kMaxDeviceBytes) + " bytes");
    auto inner = serializeBakeFile(p.file);
    if (!inner) return fail(inner.error());
    const uint32_t headerWords =
        kFixedHeaderWords + uint32_t(p.selected.size() + p.own.size()) + padWords(p.device.size());
    std::vector<uint32_t> w(headerWords, 0u);
    w[kHMagic] = kMagic, w[kHVersion] = kVersion, w[kHHeaderWords] = headerWords;
    w[kHShard] = p.shard.index, w[kHShards] = p.shard.count;
    w[kHSelected] = uint32_t(p.selected.size()), w[kHOwn] = uint32_t(p.own.size());
    w[kHDeviceBytes] = uint32_t(p.device.size());
    w[kHFingerprintLo] = uint32_t(p.fingerprint), w[kHFingerprintHi] = uint32_t(p.fingerprint >> 32);
    w[kHBuildLo] = uint32_t(p.build), w[kHBuildHi] = uint32_t(p.build >> 32);
    w[kHInnerLo] = uint32_t(inner->size()), w[kHInnerHi] = uint32_t(uint64_t(inner->size()) >> 32);
    std::copy(p.selected.begin(), p.selected.end(), w.begin() + kFixedHeaderWords);
    std::copy(p.own.begin(), p.own.end(), w.begin() + kFixedHeaderWords + p.selected.size());
    std::memcpy(w.data() + kFixedHeaderWords + p.selected.size() + p.own.size(), p.device.data(),
                p.device.size());
    w[kHChecksum] = stat::checksumWords(w.data(), headerWords, kHChecksum);
    w.insert(w.end(), inner->begin(), inner->end());
    return w;
}

Result<BakePart> parseBakePart(const std::string& name, const uint32_t* w, size_t count) {
    auto bad = [&](const std::string& why) { return fail(name + ": " + why); };
    if (count < kFixedHeaderWords)
        return bad("file is " + std::to_string(count * 4) + " bytes, shorter than a bake part's " +
                   std::to_string(kFixedHeaderWords * 4) + "-byte header");
    if (w[kHMagic] == bakefmt::kMagic)
        return bad("a whole bake file, not a part of a sharded bake (bake --shard I/N writes parts)");
    if (w[kHMagic] != kMagic) return bad("not a manylights bake part (wrong magic)");
    if (w[kHVersion] != kVersion)
        return bad("unsupported bake part version " + std::to_string(w[kHVersion]) + " (this build reads " +
                   std::to_string(kVersion) + ")");
    const uint64_t selected = w[kHSelected], own = w[kHOwn], device = w[kHDeviceBytes];
    if (selected == 0 || selected > kMaxLights || own > selected)
        return bad("header: light counts " + std::to_string(selected) + " selected, " + std::to_string(own) +
                   " own are out of range");
    if (device == 0 || device > kMaxDeviceBytes)
        return bad("header: device string length " + std::to_string(device) + " out of range");
    const uint64_t headerWords = kFixedHeaderWords + selected + own + padWords(size_t(device));
    if (w[kHHeaderWords] != headerWords)
        return bad("header: header size " + std::to_string(w[kHHeaderWords]) +
                   " words does not match its lists (" + std::to_string(headerWords) + ")");
    if (headerWords > count) return bad("header: truncated (file ends inside the header)");
    if (w[kHChecksum] != stat::checksumWords(w, size_t(headerWords), kHChecksum))
        return bad("header: checksum mismatch");
    if (w[kHReserved] != 0) return bad("header: reserved word is not 0");
    BakePart p;
    p.shard = {w[kHShard], w[kHShards]};
    if (p.shard.count == 0 || p.shard.count > kMaxShards || p.shard.index >= p.shard.count)
        return bad("header: shard " + shardName(p.shard) + " out of range");
    const uint64_t inner = join(w[kHInnerLo], w[kHInnerHi]);
    if (headerWords + inner != count)
        return bad("file should be " + std::to_string((headerWords + inner) * 4) + " bytes but is " +
                   std::to_string(uint64_t(count) * 4) + " (truncated or extended)");
    p.fingerprint = join(w[kHFingerprintLo], w[kHFingerprintHi]);
    p.build = join(w[kHBuildLo], w[kHBuildHi]);
    const uint32_t* lists = w + kFixedHeaderWords;
    p.selected.assign(lists, lists + selected);
    p.own.assign(lists + selected, lists + selected + own);
    if (!strictlyIncreasing(p.selected) || !strictlyIncreasing(p.own))
        return bad("header: light lists are not increasing");
    if (!std::includes(p.selected.begin(), p.selected.end(), p.own.begin(), p.own.end()))
        return bad("header: the shard's lights are not all in the selection");
    const char* dev = reinterpret_cast<const char*>(lists + selected + own);
    p.device.assign(dev, size_t(device));
    if (p.device.find('\0') != std::string::npos) return bad("header: device string contains a NUL byte");
    for (size_t b = size_t(device); b < padWords(size_t(device)) * 4; ++b)
        if (dev[b] != 0) return bad("header: device string padding is not zero");
    auto file = parseBakeFile(name + ": inner bake file", w + headerWords, size_t(inner));
    if (!file) return fail(file.error());
    p.file = std::move(file.value());
    for (const BakeRecord& r : p.file.records)
        if (!std::binary_search(p.own.begin(), p.own.end(), r.light))
            return bad("record of light " + std::to_string(r.light) +
                       " which is not one of the shard's lights");
    if (p.selected.back() >= p.file.scene.lights)
        return bad("selected light " + std::to_string(p.selected.back()) + " is not below the scene's " +
                   std::to_string(p.file.scene.lights) + " lights");
    return p;
}

// The file I/O goes through io/safe_io.h like the bake file's: regular files only, an exclusive
// temporary beside the target, checked writes, no write through a symlink or over a non-regular file.
Result<void> writeBakePart(const std::string& path, const BakePart& part) {
    auto words = serializeBakePart(part);
    if (!words) return fail(path + ": " + words.error());
    if (auto v = parseBakePart(path, words->data(), words->size()); !v)
        return fail("refusing to write an invalid bake part: " + v.error());
    return io::writeFileAtomically(path, words->data(), words->size() * 4);
}

Result<BakePart> readBakePart(const std::string& path) {
    auto bytes = io::readRegularFile(path);
    if (!bytes) return fail(bytes.error());
    const size_t size = bytes->size();
    std::vector<uint32_t> words(size / 4);
    if (!words.empty()) std::memcpy(words.data(), bytes->data(), words.size() * 4);
    if (!words.empty() && words[0] != kMagic && words[0] != bakefmt::kMagic)
        return fail(path + ": not a manylights bake part (wrong magic)");
    if (size % 4 != 0)
        return fail(path + ": size " + std::to_string(size) +
                    " bytes is not a whole number of words (truncated?)");
    return parseBakePart(path, words.data(), words.size());
}

Result<BakeFile> mergeBakeParts(const std::vector<BakePart>& parts, const std::vector<std::string>& names) {
    if (parts.empty()) return fail("no parts to merge");
    const BakePart& a = parts[0];
    const std::string& an = names[0];
    for (size_t i = 1; i < parts.size(); ++i) {
        const BakePart& b = parts[i];
        const std::string& bn = names[i];
        auto differ = [&](const std::string& what, const std::string& x, const std::string& y) {
            return fail(an + " and " + bn + " are not parts of one bake: " + what + " " + x + " vs " + y);
        };
        const SceneSpec &sa = a.file.scene, &sb = b.file.scene;
        if (sa.scene != sb.scene || sa.lights != sb.lights || sa.seed != sb.seed)
            return differ("scene",
                          sa.scene + " (" + std::to_string(sa.lights) + " lights, seed " +
                              std::to_string(sa.seed) + ")",
                          sb.scene + " (" + std::to_string(sb.lights) + " lights, seed " +
                              std::to_string(sb.seed) + ")");
        if (a.fingerprint != b.fingerprint)
            return differ("scene fingerprint (the scene's geometry or lights changed between the shards)",
                          hex64(a.fingerprint), hex64(b.fingerprint));
        if (a.file.method != b.file.method)
            return differ("method", staticMethodName(a.file.method), staticMethodName(b.file.method));
        if (a.file.resolution != b.file.resolution)
            return differ("resolution", std::to_string(a.file.resolution), std::to_string(b.file.resolution));
        if (a.file.renderer != b.file.renderer)
            return differ("renderer", a.file.renderer == BakeRenderer::Gpu ? "gpu" : "cpu",
                          b.file.renderer == BakeRenderer::Gpu ? "gpu" : "cpu");
        if (a.device != b.device) return differ("device", "'" + a.device + "'", "'" + b.device + "'");
        if (a.build != b.build)
            return differ("manylights build (executable hash; bake every shard with one build)",
                          hex64(a.build), hex64(b.build));
        if (a.shard.count != b.shard.count)
            return differ("shard count", std::to_string(a.shard.count), std::to_string(b.shard.count));
        if (a.selected != b.selected)
            return differ("light selection", std::to_string(a.selected.size()) + " lights",
                          std::to_string(b.selected.size()) + " lights (or other ones)");
    }
    // Each selected light in exactly one part.
    std::map<uint32_t, size_t> owner;
    std::vector<uint32_t> doubled;
    size_t firstA = 0, firstB = 0;
    for (size_t i = 0; i < parts.size(); ++i)
        for (uint32_t l : parts[i].own) {
            auto [it, fresh] = owner.insert({l, i});
            if (!fresh) {
                if (doubled.empty()) firstA = it->second, firstB = i;
                doubled.push_back(l);
            }
        }
    if (!doubled.empty()) {
        std::sort(doubled.begin(), doubled.end());
        doubled.erase(std::unique(doubled.begin(), doubled.end()), doubled.end());
        return fail(std::string(doubled.size() == 1 ? "light " : "lights ") + lightList(doubled) +
                    " baked twice: in " + names[firstA] + " (shard " + shardName(parts[firstA].shard) +
                    ") and " + names[firstB] + " (shard " + shardName(parts[firstB].shard) + ")");
    }
    std::vector<uint32_t> missing;
    for (uint32_t l : a.selected)
        if (!owner.count(l)) missing.push_back(l);
    if (!missing.empty()) {
        std::vector<bool> present(a.shard.count, false);
        for (const BakePart& p : parts) present[p.shard.index] = true;
        std::string shards;
        for (uint32_t s = 0; s < a.shard.count; ++s)
            if (!present[s]) shards += (shards.empty() ? "" : ", ") + shardName({s, a.shard.count});
        return fail(std::string(missing.size() == 1 ? "light " : "lights ") + lightList(missing) +
                    " of the selection in no part (missing shard" +
                    (shards.find(',') != std::string::npos ? "s " : " ") +
                    (shards.empty() ? "unknown" : shards) + ")");
    }
    BakeFile out;
    out.scene = a.file.scene, out.renderer = a.file.renderer;
    out.method = a.file.method, out.resolution = a.file.resolution;
    for (const BakePart& p : parts)
        for (const BakeRecord& r : p.file.records) out.records.push_back(r);
    // bakeScene's order: by light, then cube face.
    std::sort(out.records.begin(), out.records.end(), [](const BakeRecord& x, const BakeRecord& y) {
        return x.light != y.light ? x.light < y.light : x.face < y.face;
    });
    if (out.records.empty())
        return fail("none of the " + std::to_string(a.selected.size()) +
                    " selected lights was baked (all skipped): a single bake would fail too");
    return out;
}

} // namespace ml
