#include "shadows/static/bake_file.h"

#include "io/safe_io.h"
#include "shadows/static/static_visibility.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <new>
#include <stdexcept>
#include <set>

namespace ml {

using namespace bakefmt;

// The file is defined as little-endian words; on a little-endian host the words are the bytes.
static_assert(std::endian::native == std::endian::little, "bake files assume a little-endian host");

namespace {

constexpr size_t kNoSkip = std::numeric_limits<size_t>::max();

uint32_t sceneWords(size_t bytes) {
    return uint32_t((bytes + 3) / 4);
}
uint32_t floatBits(float f) {
    return std::bit_cast<uint32_t>(f);
}
float bitsFloat(uint32_t w) {
    return std::bit_cast<float>(w);
}
uint64_t join(uint32_t lo, uint32_t hi) {
    return uint64_t(lo) | uint64_t(hi) << 32;
}

bool validMethod(uint32_t m) {
    return m >= uint32_t(StaticMethod::SM) && m <= uint32_t(StaticMethod::CPVS);
}

// Checks everything, and fills `out` when it is not null (validation alone needs no copy of the data).
Result<void> parseWords(const std::string& name, const uint32_t* w, size_t count, BakeFile* out) {
    auto bad = [&](const std::string& why) { return fail(name + ": " + why); };
    if (count < kFixedHeaderWords)
        return bad("file is " + std::to_string(count * 4) + " bytes, shorter than the " +
                   std::to_string(kFixedHeaderWords * 4) + "-byte header");
    if (w[kHMagic] == kPartMagic)
        return bad("one part of a sharded bake (bake --shard), not a whole bake file: merge the parts "
                   "with `manylights merge`");
    if (w[kHMagic] != kMagic) return bad("not a manylights bake file (wrong magic)");
    if (w[kHVersion] != kVersion && w[kHVersion] != kVersionFixed && w[kHVersion] != kVersionFitted)
        return bad("unsupported version " + std::to_string(w[kHVersion]) + " (this build reads " +
                   std::to_string(kVersionFixed) + " to " + std::to_string(kVersionFitted) + ")");
    const uint32_t version = w[kHVersion];
    // The header's length must be known (and inside the file) before its checksum can be computed.
    const uint32_t sceneBytes = w[kHSceneBytes];
    if (sceneBytes == 0 || sceneBytes > kMaxSceneBytes)
        return bad("header: scene string length " + std::to_string(sceneBytes) + " outside 1.." +
                   std::to_string(kMaxSceneBytes));
    // Version 1 has no need block (the word was reserved, 0); version 2 always has one.
    const uint32_t needWords = w[kHNeedWords];
    if (version == kVersionFixed && needWords != 0) return bad("header: reserved word is not 0");
    // Version 3: a need block or none (0 words).
    if ((version == kVersion || (version == kVersionFitted && needWords != 0)) &&
        (needWords < kNeedFixedWords ||
         needWords > kNeedFixedWords + kMaxRegionBytes / 4 + kMaxRecords * kNeedEntryWords))
        return bad("header: need block of " + std::to_string(needWords) + " words out of range");
    const uint32_t headerWords = kFixedHeaderWords + sceneWords(sceneBytes) + needWords;
    if (w[kHHeaderWords] != headerWords)
        return bad("header: header size " + std::to_string(w[kHHeaderWords]) + " words does not match its " +
                   std::to_string(sceneBytes) + "-byte scene string and " + std::to_string(needWords) +
                   "-word need block");
    if (headerWords > count) return bad("header: truncated (file ends inside the header)");
    if (w[kHChecksum] != stat::checksumWords(w, headerWords, kHChecksum))
        return bad("header: checksum mismatch");
    if ((w[kHFlags] & ~kFlagGpuRenderer) != 0)
        return bad("header: unknown flags " + std::to_string(w[kHFlags]));
    if (!validMethod(w[kHMethod])) return bad("header: unknown method " + std::to_string(w[kHMethod]));
    const StaticMethod method = StaticMethod(w[kHMethod]);
    const uint32_t res = w[kHResolution];
    if (res == 0 || res > kMaxResolution)
        return bad("header: resolution " + std::to_string(res) + " out of range");
    const uint32_t records = w[kHRecordCount];
    if (records > kMaxRecords)
        return bad("header: record count " + std::to_string(records) + " out of range");
    if (w[kHSceneLights] == 0) return bad("header: scene light count is 0");
    if (w[kHRecordWords] != kRecordWords)
        return bad("header: record size " + std::to_string(w[kHRecordWords]) + " words (expected " +
                   std::to_string(kRecordWords) + ")");
    if (w[kHRecordOffset] != headerWords) return bad("header: record table does not follow the header");
    const uint64_t total = join(w[kHTotalLo], w[kHTotalHi]);
    if (total != count)
        return bad("header: file should be " + std::to_string(total * 4) + " bytes but is " +
                   std::to_string(uint64_t(count) * 4) + " (truncated or extended)");
    std::string scene(reinterpret_cast<const char*>(w + kFixedHeaderWords), sceneBytes);
    if (scene.find('\0') != std::string::npos) return bad("header: scene string contains a NUL byte");
    for (uint32_t b = sceneBytes; b < sceneWords(sceneBytes) * 4; ++b)
        if (reinterpret_cast<const char*>(w + kFixedHeaderWords)[b] != 0)
            return bad("header: scene string padding is not zero");
    // The need block (version 2): per selected light, its resolution and why.
    BakeNeed need;
    if (needWords) {
        const uint32_t* nb = w + kFixedHeaderWords + sceneWords(sceneBytes);
        auto badNeed = [&](const std::string& why) { return bad("need block: " + why); };
        const uint32_t entries = nb[0], regionBytes = nb[5];
        need.width = nb[1], need.height = nb[2], need.minRes = nb[3], need.maxRes = nb[4],
        need.samples = nb[6];
        if (nb[7] != 0) return badNeed("reserved word is not 0");
        if (regionBytes == 0 || regionBytes > kMaxRegionBytes)
            return badNeed("region string length " + std::to_string(regionBytes) + " outside 1.." +
                           std::to_string(kMaxRegionBytes));
        if (uint64_t(needWords) !=
            kNeedFixedWords + sceneWords(regionBytes) + uint64_t(entries) * kNeedEntryWords)
            return badNeed("size does not match its " + std::to_string(entries) + " entries");
        if (need.width == 0 || need.height == 0 || need.samples == 0 || need.minRes == 0 ||
            need.minRes > need.maxRes || need.maxRes != res)
            return badNeed("image size, camera samples or resolution range invalid (the maximum must be "
                           "the header's resolution)");
        const char* region = reinterpret_cast<const char*>(nb + kNeedFixedWords);
        need.region.assign(region, regionBytes);
        if (need.region.find('\0') != std::string::npos) return badNeed("region string contains a NUL byte");
        for (uint32_t b = regionBytes; b < sceneWords(regionBytes) * 4; ++b)
            if (region[b] != 0) return badNeed("region string padding is not zero");
        const uint32_t* e = nb + kNeedFixedWords + sceneWords(regionBytes);
        for (uint32_t i = 0; i < entries; ++i, e += kNeedEntryWords) {
            LightNeed n;
            n.light = e[0], n.resolution = e[1], n.reason = NeedReason(e[2] & 0xFFu);
            n.raysCapped = (e[2] >> 8) != 0;
            n.distance = bitsFloat(e[3]), n.sample = e[4], n.needed = bitsFloat(e[5]);
            n.receivers = e[6], n.seen = e[7];
            const std::string at = "entry " + std::to_string(i) + ": ";
            if (n.light >= w[kHSceneLights] || (i > 0 && n.light <= need.lights.back().light))
                return badNeed(at + "light " + std::to_string(n.light) +
                               " out of range or not in increasing order");
            if ((e[2] & 0xFFu) < uint32_t(NeedReason::Footprint) ||
                (e[2] & 0xFFu) > uint32_t(NeedReason::NoCaster) || (e[2] >> 9) != 0)
                return badNeed(at + "unknown reason " + std::to_string(e[2]));
            if ((n.reason == NeedReason::NoCaster) != (n.resolution == 0))
                return badNeed(at + "resolution 0 is for 'no caster' only, and only it");
            if (n.resolution != 0 && (n.resolution < need.minRes || n.resolution > need.maxRes))
                return badNeed(at + "resolution " + std::to_string(n.resolution) + " outside the range");
            if (!std::isfinite(n.distance) || !std::isfinite(n.needed) || n.distance < 0.0f ||
                n.needed < 0.0f || n.seen > n.receivers ||
                (n.reason != NeedReason::NoCaster && n.reason != NeedReason::NotSeen &&
                 n.sample >= need.samples))
                return badNeed(at + "depth, need, sample or counts out of range");
            need.lights.push_back(n);
        }
    }
    const uint64_t dataBegin = uint64_t(headerWords) + uint64_t(records) * kRecordWords;
    if (dataBegin > count) return bad("record table: truncated (file ends inside the record table)");

    if (out) {
        out->scene = {scene, w[kHSceneLights], w[kHSeed]};
        out->renderer = (w[kHFlags] & kFlagGpuRenderer) ? BakeRenderer::Gpu : BakeRenderer::Cpu;
        out->method = method;
        out->resolution = res;
        out->records.clear();
        out->records.reserve(records);
    }
    std::set<uint64_t> lightsSeen; // light * 8 + face
    uint64_t expectedOffset = dataBegin;
    for (uint32_t r = 0; r < records; ++r) {
        const uint32_t* rec = w + headerWords + size_t(r) * kRecordWords;
        auto badRec = [&](const std::string& why) { return bad("record " + std::to_string(r) + ": " + why); };
        if (rec[kRChecksum] != stat::checksumWords(rec, kRecordWords, kRChecksum))
            return badRec("record checksum mismatch");
        if (rec[kRFace] > 5) return badRec("cube face " + std::to_string(rec[kRFace]) + " is not 0..5");
        for (uint32_t i = kRFitMargin + 1; i < kRecordWords; ++i)
            if (rec[i] != 0) return badRec("reserved word " + std::to_string(i) + " is not 0");
        if (rec[kROrtho] != 0 && version != kVersionFitted)
            return badRec("a directional record of bake format version " + std::to_string(version) +
                          " (a square map with log depth slices, from a build before fitted directional "
                          "maps): this build "
                          "reads directional records of version " +
                          std::to_string(kVersionFitted) + " only; re-bake the light");
        if (rec[kROrtho] == 0 && (rec[kROrthoHalfY] != 0 || rec[kRFitMargin] != 0))
            return badRec("reserved word 30 or 31 is not 0 (not a directional record)");
        if (version != kVersionFitted && (rec[kROrthoHalfY] != 0 || rec[kRFitMargin] != 0))
            return badRec("reserved word 30 or 31 is not 0");
        if (rec[kRLight] >= w[kHSceneLights])
            return badRec("light " + std::to_string(rec[kRLight]) + " is not below the scene's " +
                          std::to_string(w[kHSceneLights]) + " lights");
        if (!lightsSeen.insert(uint64_t(rec[kRLight]) * 8u + rec[kRFace]).second)
            return badRec("light " + std::to_string(rec[kRLight]) + " face " + std::to_string(rec[kRFace]) +
                          " appears twice");
        if (rec[kRMethod] != uint32_t(method)) return badRec("method differs from the file's");
        uint32_t recRes = res;
        if (needWords) {
            // Entries are in increasing light order: a binary search.
            auto it = std::lower_bound(need.lights.begin(), need.lights.end(), rec[kRLight],
                                       [](const LightNeed& a, uint32_t l) { return a.light < l; });
            const LightNeed* n = it != need.lights.end() && it->light == rec[kRLight] ? &*it : nullptr;
            if (!n || n->resolution == 0)
                return badRec("light " + std::to_string(rec[kRLight]) +
                              " has no need entry with a resolution");
            recRes = n->resolution;
        }
        if (rec[kRResolution] != recRes)
            return badRec(needWords ? "resolution differs from its need entry's"
                                    : "resolution differs from the file's");
        LightFrustum f;
        float* m = &f.view[0][0];
        for (int i = 0; i < 16; ++i) m[i] = bitsFloat(rec[kRView + i]);
        f.fov = bitsFloat(rec[kRFov]), f.nearPlane = bitsFloat(rec[kRNear]),
        f.farPlane = bitsFloat(rec[kRFar]);
        f.orthoHalf = bitsFloat(rec[kROrtho]);
        f.orthoHalfY = bitsFloat(rec[kROrthoHalfY]), f.fitMargin = bitsFloat(rec[kRFitMargin]);
        for (int i = 0; i < 16; ++i)
            if (!std::isfinite(m[i])) return badRec("view matrix is not finite");
        // The module's shadow record keeps the view as a rotation and a translation (GpuShadowRecord).
        if (!rigidView(f.view)) return badRec("view matrix is not a rigid motion (rotation and translation)");
        if (rec[kROrtho] != 0) {
            if (!(f.orthoHalf > 0.0f && std::isfinite(f.orthoHalf) && f.fov == 0.0f && rec[kRFace] == 0))
                return badRec("orthographic half side not finite and > 0, or fov/face not 0");
            if (!(f.orthoHalfY > 0.0f && f.orthoHalfY <= f.orthoHalf && f.fitMargin >= 0.0f &&
                  f.fitMargin < f.orthoHalfY))
                return badRec("directional fit: half height " + std::to_string(f.orthoHalfY) +
                              " not in (0, " + std::to_string(f.orthoHalf) + "] or margin " +
                              std::to_string(f.fitMargin) + " not in [0, half height)");
        } else if (!(f.fov > 0.0f && f.fov < 3.14159f)) {
            return badRec("field of view out of range");
        }
        if (!(f.nearPlane > 0.0f && f.farPlane > f.nearPlane && std::isfinite(f.farPlane)))
            return badRec("near/far planes out of range");
        if (f.orthographic() && !(f.farPlane - f.nearPlane > 2.0f * f.fitMargin))
            return badRec("directional fit: depth range not wider than twice the margin");
        const uint64_t offset = join(rec[kROffsetLo], rec[kROffsetHi]);
        const uint64_t words = join(rec[kRWordsLo], rec[kRWordsHi]);
        // Data blocks are packed back to back in record order: this one rule excludes overlaps, gaps and
        // blocks inside the header or the record table.
        if (offset != expectedOffset)
            return badRec("data offset " + std::to_string(offset) + " (expected " +
                          std::to_string(expectedOffset) + ": data blocks must follow each other)");
        if (words == 0) return badRec("data is empty");
        if (words > count - offset)
            return badRec("data of " + std::to_string(words) + " words runs past the end of the file");
        const uint32_t* data = w + offset;
        if (rec[kRDataChecksum] != stat::checksumWords(data, size_t(words), kNoSkip))
            return badRec("data checksum mismatch");
        if (auto v = validateStatic(method, data, size_t(words)); !v) return badRec(v.error());
        if (staticResolution(method, data) != recRes)
            return badRec("data resolution differs from the record's");
        if (method == StaticMethod::CPVS &&
            (data[kCpvsHNearBits] != rec[kRNear] || data[kCpvsHFarBits] != rec[kRFar]))
            return badRec("CPVS depth range differs from the record's frustum");
        // Directional records slice CPVS depth linearly, spot and point ones by eq. 1; a fitted SM
        // stores exactly the rows in the light's volume.
        if (method == StaticMethod::CPVS &&
            data[kCpvsHSlicing] != uint32_t(f.orthographic() ? CpvsSlicing::Linear : CpvsSlicing::Log))
            return badRec(f.orthographic() ? "directional CPVS is not sliced linearly"
                                           : "spot/point CPVS is not sliced by eq. 1");
        if (method == StaticMethod::SM && smRows(data, 0) != f.mapRows(recRes))
            return badRec("SM stores " + std::to_string(smRows(data, 0)) + " rows, the frustum covers " +
                          std::to_string(f.mapRows(recRes)));
        expectedOffset = offset + words;
        if (out)
            out->records.push_back(
                {rec[kRLight], rec[kRFace], method, recRes, f, std::vector<uint32_t>(data, data + words)});
    }
    if (expectedOffset != count)
        return bad(std::to_string(count - expectedOffset) + " words after the last record's data");
    // Every light the need block gives a resolution has its records (none dropped).
    for (const LightNeed& n : need.lights)
        if (n.resolution != 0 && !lightsSeen.count(uint64_t(n.light) * 8u))
            return bad("need block: light " + std::to_string(n.light) + " has a resolution but no record");
    if (out && needWords) out->hasNeed = true, out->need = std::move(need);
    return {};
}

} // namespace

Result<std::vector<uint32_t>> serializeBakeFile(const BakeFile& file) {
    const SceneSpec& s = file.scene;
    if (s.scene.empty() || s.scene.size() > kMaxSceneBytes || s.scene.find('\0') != std::string::npos)
        return fail("bake file: scene string must be 1.." + std::to_string(kMaxSceneBytes) +
                    " bytes without NUL");
    if (!validMethod(uint32_t(file.method))) return fail("bake file: no method");
    if (file.records.size() > kMaxRecords) return fail("bake file: too many records");
    if (file.hasNeed && (file.need.region.empty() || file.need.region.size() > kMaxRegionBytes ||
                         file.need.region.find('\0') != std::string::npos))
        return fail("bake file: need region string must be 1.." + std::to_string(kMaxRegionBytes) +
                    " bytes without NUL");
    const uint32_t needWords = file.hasNeed ? uint32_t(kNeedFixedWords + sceneWords(file.need.region.size()) +
                                                       file.need.lights.size() * kNeedEntryWords)
                                            : 0u;
    const uint32_t headerWords = kFixedHeaderWords + sceneWords(s.scene.size()) + needWords;
    uint64_t total = headerWords + uint64_t(file.records.size()) * kRecordWords;
    for (const BakeRecord& r : file.records) total += r.data.size();
    std::vector<uint32_t> w(size_t(total), 0u); // zero-filled: padding and reserved words are defined

    w[kHMagic] = kMagic, w[kHVersion] = bakeFileVersion(file), w[kHNeedWords] = needWords,
    w[kHFlags] = file.renderer == BakeRenderer::Gpu ? kFlagGpuRenderer : 0u, w[kHHeaderWords] = headerWords;
    w[kHMethod] = uint32_t(file.method), w[kHResolution] = file.resolution;
    w[kHRecordCount] = uint32_t(file.records.size());
    w[kHSceneLights] = s.lights, w[kHSeed] = s.seed, w[kHSceneBytes] = uint32_t(s.scene.size());
    w[kHRecordOffset] = headerWords, w[kHRecordWords] = kRecordWords;
    w[kHTotalLo] = uint32_t(total), w[kHTotalHi] = uint32_t(total >> 32);
    std::memcpy(w.data() + kFixedHeaderWords, s.scene.data(), s.scene.size());
    if (file.hasNeed) {
        const BakeNeed& n = file.need;
        uint32_t* nb = w.data() + kFixedHeaderWords + sceneWords(s.scene.size());
        nb[0] = uint32_t(n.lights.size()), nb[1] = n.width, nb[2] = n.height, nb[3] = n.minRes;
        nb[4] = n.maxRes, nb[5] = uint32_t(n.region.size()), nb[6] = n.samples;
        std::memcpy(nb + kNeedFixedWords, n.region.data(), n.region.size());
        uint32_t* e = nb + kNeedFixedWords + sceneWords(n.region.size());
        for (const LightNeed& l : n.lights) {
            e[0] = l.light, e[1] = l.resolution, e[2] = uint32_t(l.reason) | (l.raysCapped ? 1u << 8 : 0u);
            e[3] = floatBits(l.distance), e[4] = l.sample, e[5] = floatBits(l.needed);
            e[6] = l.receivers, e[7] = l.seen;
            e += kNeedEntryWords;
        }
    }
    w[kHChecksum] = stat::checksumWords(w.data(), headerWords, kHChecksum);

    uint64_t offset = headerWords + uint64_t(file.records.size()) * kRecordWords;
    for (size_t r = 0; r < file.records.size(); ++r) {
        const BakeRecord& br = file.records[r];
        uint32_t* rec = w.data() + headerWords + r * kRecordWords;
        rec[kRLight] = br.light, rec[kRMethod] = uint32_t(br.method), rec[kRResolution] = br.resolution;
        rec[kRFace] = br.face;
        const float* m = &br.frustum.view[0][0];
        for (int i = 0; i < 16; ++i) rec[kRView + i] = floatBits(m[i]);
        rec[kRFov] = floatBits(br.frustum.fov);
        rec[kROrtho] = br.frustum.orthographic() ? floatBits(br.frustum.orthoHalf) : 0u;
        rec[kROrthoHalfY] = br.frustum.orthographic() ? floatBits(br.frustum.orthoHalfY) : 0u;
        rec[kRFitMargin] = br.frustum.orthographic() ? floatBits(br.frustum.fitMargin) : 0u;
        rec[kRNear] = floatBits(br.frustum.nearPlane), rec[kRFar] = floatBits(br.frustum.farPlane);
        rec[kROffsetLo] = uint32_t(offset), rec[kROffsetHi] = uint32_t(offset >> 32);
        rec[kRWordsLo] = uint32_t(br.data.size()), rec[kRWordsHi] = uint32_t(uint64_t(br.data.size()) >> 32);
        if (!br.data.empty()) std::memcpy(w.data() + offset, br.data.data(), br.data.size() * 4);
        rec[kRDataChecksum] = stat::checksumWords(br.data.data(), br.data.size(), kNoSkip);
        rec[kRChecksum] = stat::checksumWords(rec, kRecordWords, kRChecksum);
        offset += br.data.size();
    }
    return w;
}

Result<BakeFile> parseBakeFile(const std::string& name, const uint32_t* words, size_t count) {
    BakeFile f;
    if (auto r = parseWords(name, words, count, &f); !r) return fail(r.error());
    return f;
}

Result<void> writeBakeFile(const std::string& path, const BakeFile& file) {
    auto words = serializeBakeFile(file);
    if (!words) return fail(path + ": " + words.error());
    // Never write a file the reader would reject: the same checks, before anything touches the disk.
    if (auto v = parseWords(path, words->data(), words->size(), nullptr); !v)
        return fail("refusing to write an invalid bake file: " + v.error());
    // A fresh temporary beside the target, renamed over it (io/safe_io.h): an interrupted write never
    // leaves a half file under `path`, and a symlink or device at `path` is refused, not written through.
    return io::writeFileAtomically(path, words->data(), words->size() * 4);
}

Result<BakeFile> readBakeFile(const std::string& path) {
    // Regular files only (a directory or FIFO gets one line, not an allocation or a hang).
    // The header first: a file that is not a bake file, or whose size differs from the one its header
    // states (say a sparse file of terabytes), is refused before room for it is allocated.
    uint64_t fileSize = 0;
    auto head = io::readRegularFileHead(path, kFixedHeaderWords * 4, &fileSize);
    if (!head) return fail(head.error());
    uint32_t h[kFixedHeaderWords] = {};
    if (!head->empty()) std::memcpy(h, head->data(), head->size());
    if (head->size() >= 4 && h[kHMagic] == kPartMagic)
        return fail(path +
                    ": one part of a sharded bake (bake --shard), not a whole bake file: merge the parts "
                    "with `manylights merge`");
    if (head->size() >= 4 && h[kHMagic] != kMagic)
        return fail(path + ": not a manylights bake file (wrong magic)");
    if (fileSize % 4 != 0)
        return fail(path + ": size " + std::to_string(fileSize) +
                    " bytes is not a whole number of words (truncated?)");
    const uint64_t stated = join(h[kHTotalLo], h[kHTotalHi]);
    if (head->size() == kFixedHeaderWords * 4 && h[kHVersion] != kVersion && h[kHVersion] != kVersionFixed &&
        h[kHVersion] != kVersionFitted)
        return fail(path + ": unsupported version " + std::to_string(h[kHVersion]) + " (this build reads " +
                    std::to_string(kVersionFixed) + " to " + std::to_string(kVersionFitted) + ")");
    if (head->size() == kFixedHeaderWords * 4 && stated != fileSize / 4)
        return fail(path + ": header: file should be " + std::to_string(stated) + " words but is " +
                    std::to_string(fileSize / 4) + " (truncated or extended)");
    // Then the whole file (it is uploaded as is); a size the machine cannot hold is an error line, not
    // an abort.
    std::vector<uint32_t> words;
    Result<uint64_t> size = fail("");
    try {
        size = io::readRegularFile(path, UINT64_MAX, [&](uint64_t bytes) {
            words.assign(size_t((bytes + 3) / 4), 0u);
            return reinterpret_cast<unsigned char*>(words.data());
        });
    } catch (const std::bad_alloc&) {
        return fail(path + ": too large to read into memory");
    } catch (const std::length_error&) {
        return fail(path + ": too large to read into memory");
    }
    if (!size) return fail(size.error());
    // Name the more useful problem first: some other file, rather than a bake file cut mid-word.
    if (size.value() >= 4 && words[0] != kMagic)
        return fail(path + ": not a manylights bake file (wrong magic)");
    if (size.value() % 4 != 0)
        return fail(path + ": size " + std::to_string(size.value()) +
                    " bytes is not a whole number of words (truncated?)");
    return parseBakeFile(path, words.data(), words.size());
}

BakeBytes bakeFileBytes(const BakeFile& file, std::vector<BakeRecordBytes>* perRecord) {
    BakeBytes b;
    b.headers = uint64_t(kFixedHeaderWords + sceneWords(file.scene.scene.size())) * 4;
    if (file.hasNeed) // the need block
        b.headers += (uint64_t(kNeedFixedWords) + sceneWords(file.need.region.size()) +
                      uint64_t(file.need.lights.size()) * kNeedEntryWords) *
                     4;
    if (perRecord) perRecord->clear();
    for (const BakeRecord& r : file.records) {
        stat::ByteBreakdown p = breakdownStatic(r.method, r.data.data(), r.data.size());
        b.headers += kRecordWords * 4 + p.header;
        b.skipList += p.skipList, b.bounds += p.bounds, b.nodes += p.nodes, b.treelets += p.treelets;
        b.values += p.values, b.factors += p.factors;
        if (perRecord) perRecord->push_back({r.light, p, kRecordWords * 4});
    }
    return b;
}

} // namespace ml
