// Tile parts: one light's tiles baked by several processes and merged (see bake_tile_part.h).
#include "bake/bake_tile_part.h"

#include "bake/bake.h"
#include "bake/scene_casters.h"
#include "io/safe_io.h"

#include <algorithm>
#include <cstring>

namespace ml {

namespace {

constexpr uint32_t kMagic = stat::fourcc('M', 'L', 'T', 'P');
// Version 2: a plane table (DAG-MH's planar trees) and 4 words a node (the plane id).
constexpr uint32_t kVersion = 2;
constexpr uint32_t kPlaneWords = 4, kNodeWords = 4, kTileWords = 6;
constexpr uint32_t kFrustumWords = 22;
constexpr uint32_t kFixedWords = 20 + kFrustumWords;
constexpr uint32_t kMaxSceneBytes = 4096;
enum : uint32_t {
    kHMagic,
    kHVersion,
    kHHeaderWords,
    kHShard,
    kHShards,
    kHMethod,
    kHResolution,
    kHTile,
    kHLight,
    kHFace,
    kHRenderer,
    kHSceneLights,
    kHSeed,
    kHSceneBytes,
    kHTiles,
    kHPlanes,
    kHFingerprintLo,
    kHFingerprintHi,
    kHBuildLo,
    kHBuildHi,
    kHFrustum,
};

uint32_t floatBits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}
float bitsFloat(uint32_t u) {
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

void putFrustum(uint32_t* w, const LightFrustum& f) {
    const float* m = &f.view[0][0];
    for (int i = 0; i < 16; ++i) w[i] = floatBits(m[i]);
    w[16] = floatBits(f.fov), w[17] = floatBits(f.nearPlane), w[18] = floatBits(f.farPlane);
    w[19] = floatBits(f.orthoHalf), w[20] = floatBits(f.orthoHalfY), w[21] = floatBits(f.fitMargin);
}
LightFrustum getFrustum(const uint32_t* w) {
    LightFrustum f;
    float* m = &f.view[0][0];
    for (int i = 0; i < 16; ++i) m[i] = bitsFloat(w[i]);
    f.fov = bitsFloat(w[16]), f.nearPlane = bitsFloat(w[17]), f.farPlane = bitsFloat(w[18]);
    f.orthoHalf = bitsFloat(w[19]), f.orthoHalfY = bitsFloat(w[20]), f.fitMargin = bitsFloat(w[21]);
    return f;
}

bool isMhFamily(StaticMethod m) {
    return m == StaticMethod::MH || m == StaticMethod::MMH || m == StaticMethod::DAGMH;
}

} // namespace

Result<std::vector<uint32_t>> serializeTilePart(const TilePart& p) {
    if (p.scene.scene.size() > kMaxSceneBytes) return fail("scene string longer than 4096 bytes");
    const uint32_t sceneWords = uint32_t((p.scene.scene.size() + 3) / 4);
    if (p.planes.size() > DualRasterizer::kMaxDepthPlanes) return fail("too many depth planes");
    std::vector<uint32_t> w(kFixedWords + sceneWords, 0u);
    w[kHMagic] = kMagic, w[kHVersion] = kVersion, w[kHHeaderWords] = uint32_t(w.size());
    w[kHShard] = p.shard.index, w[kHShards] = p.shard.count, w[kHMethod] = uint32_t(p.method);
    w[kHResolution] = p.resolution, w[kHTile] = p.tile, w[kHLight] = p.light, w[kHFace] = p.face;
    w[kHRenderer] = uint32_t(p.renderer), w[kHSceneLights] = p.scene.lights, w[kHSeed] = p.scene.seed;
    w[kHSceneBytes] = uint32_t(p.scene.scene.size()), w[kHTiles] = uint32_t(p.tiles.size());
    w[kHPlanes] = uint32_t(p.planes.size());
    w[kHFingerprintLo] = uint32_t(p.fingerprint), w[kHFingerprintHi] = uint32_t(p.fingerprint >> 32);
    w[kHBuildLo] = uint32_t(p.build), w[kHBuildHi] = uint32_t(p.build >> 32);
    putFrustum(&w[kHFrustum], p.frustum);
    if (!p.scene.scene.empty()) std::memcpy(&w[kFixedWords], p.scene.scene.data(), p.scene.scene.size());
    for (const DepthPlane& q : p.planes)
        w.insert(w.end(),
                 {uint32_t(uint64_t(q.a)), uint32_t(uint64_t(q.a) >> 32), uint32_t(q.dx), uint32_t(q.dy)});
    w[kHHeaderWords] = uint32_t(w.size());
    for (const auto& [index, t] : p.tiles) {
        w.insert(w.end(), {index, t.lo, t.hi, t.flags, t.plane, uint32_t(t.nodes.size())});
        for (const MhPackedNode& n : t.nodes) w.insert(w.end(), {n.lo, n.hi, n.bits, n.plane});
    }
    w.push_back(0u);
    w.back() = stat::checksumWords(w.data(), w.size(), w.size() - 1);
    return w;
}

Result<TilePart> parseTilePart(const std::string& name, const uint32_t* w, size_t count) {
    auto bad = [&](const std::string& why) { return fail(name + ": tile part: " + why); };
    if (count < kFixedWords + 1) return bad("shorter than its header");
    if (w[kHMagic] != kMagic) return bad("wrong magic");
    if (w[kHVersion] != kVersion) return bad("unsupported version " + std::to_string(w[kHVersion]));
    if (w[count - 1] != stat::checksumWords(w, count, count - 1)) return bad("checksum mismatch");
    TilePart p;
    p.shard = {w[kHShard], w[kHShards]};
    if (p.shard.count == 0 || p.shard.count > partfmt::kMaxShards || p.shard.index >= p.shard.count)
        return bad("shard " + std::to_string(p.shard.index) + "/" + std::to_string(p.shard.count) +
                   " out of range");
    if (!isMhFamily(StaticMethod(w[kHMethod])))
        return bad("method " + std::to_string(w[kHMethod]) + " is not mh, mmh or dagmh");
    p.method = StaticMethod(w[kHMethod]);
    p.resolution = w[kHResolution], p.tile = w[kHTile], p.light = w[kHLight], p.face = w[kHFace];
    auto grid = mhTileGrid(p.resolution, p.tile);
    if (!grid) return bad(grid.error());
    if (p.tile != grid->tile) return bad("tile side larger than the map");
    if (p.face > 5) return bad("face " + std::to_string(p.face) + " out of range");
    if (w[kHRenderer] > 1) return bad("renderer " + std::to_string(w[kHRenderer]) + " unknown");
    p.renderer = BakeRenderer(w[kHRenderer]);
    p.scene.lights = w[kHSceneLights], p.scene.seed = w[kHSeed];
    const uint32_t sceneBytes = w[kHSceneBytes], sceneWords = (sceneBytes + 3) / 4;
    const uint64_t planes = w[kHPlanes];
    if (sceneBytes > kMaxSceneBytes || planes > DualRasterizer::kMaxDepthPlanes ||
        w[kHHeaderWords] != kFixedWords + sceneWords + kPlaneWords * planes)
        return bad("header size does not match its scene string and planes");
    if (uint64_t(w[kHHeaderWords]) + 1 > count) return bad("scene string or planes past the end");
    p.scene.scene.assign(reinterpret_cast<const char*>(&w[kFixedWords]), sceneBytes);
    p.planes.resize(size_t(planes));
    for (size_t i = 0; i < p.planes.size(); ++i) {
        const uint32_t* q = &w[kFixedWords + sceneWords + kPlaneWords * i];
        p.planes[i] = {int64_t(uint64_t(q[1]) << 32 | q[0]), int32_t(q[2]), int32_t(q[3])};
    }
    p.fingerprint = uint64_t(w[kHFingerprintHi]) << 32 | w[kHFingerprintLo];
    p.build = uint64_t(w[kHBuildHi]) << 32 | w[kHBuildLo];
    p.frustum = getFrustum(&w[kHFrustum]);
    size_t at = w[kHHeaderWords];
    const size_t end = count - 1;
    const uint32_t tiles = w[kHTiles];
    if (tiles > grid->count())
        return bad(std::to_string(tiles) + " tiles for a grid of " + std::to_string(grid->count()));
    for (uint32_t i = 0; i < tiles; ++i) {
        if (end - at < kTileWords) return bad("tile " + std::to_string(i) + " past the end");
        const uint32_t index = w[at], nodes = w[at + 5];
        if (index >= grid->count() || index % p.shard.count != p.shard.index)
            return bad("tile index " + std::to_string(index) + " is not shard " +
                       std::to_string(p.shard.index) + "'s");
        if (!p.tiles.empty() && index <= p.tiles.back().first) return bad("tile indices not increasing");
        if (w[at + 3] > 3)
            return bad("tile " + std::to_string(index) + ": flags " + std::to_string(w[at + 3]));
        if ((end - at - kTileWords) / kNodeWords < nodes)
            return bad("tile " + std::to_string(index) + ": nodes past the end");
        MhTile t;
        t.lo = w[at + 1], t.hi = w[at + 2], t.flags = uint8_t(w[at + 3]), t.plane = w[at + 4], t.built = true;
        t.nodes.resize(nodes);
        for (uint32_t k = 0; k < nodes; ++k) {
            const uint32_t* q = &w[at + kTileWords + size_t(kNodeWords) * k];
            t.nodes[k] = {q[0], q[1], q[2], q[3]};
        }
        if (auto v = validateMhTile(*grid, t, p.planes.size()); !v)
            return bad("tile " + std::to_string(index) + ": " + v.error());
        at += kTileWords + size_t(kNodeWords) * nodes;
        p.tiles.push_back({index, std::move(t)});
    }
    if (at != end) return bad("words after the last tile");
    return p;
}

Result<void> writeTilePart(const std::string& path, const TilePart& part) {
    auto words = serializeTilePart(part);
    if (!words) return fail(path + ": " + words.error());
    return io::writeFileAtomically(path, words->data(), words->size() * 4);
}

Result<TilePart> readTilePart(const std::string& path) {
    auto bytes = io::readRegularFile(path);
    if (!bytes) return fail(bytes.error());
    if (bytes->size() % 4 != 0)
        return fail(path + ": size " + std::to_string(bytes->size()) +
                    " bytes is not a whole number of words");
    std::vector<uint32_t> words(bytes->size() / 4);
    if (!words.empty()) std::memcpy(words.data(), bytes->data(), bytes->size());
    return parseTilePart(path, words.data(), words.size());
}

bool isTilePartFile(const std::string& path) {
    uint64_t size = 0;
    auto head = io::readRegularFileHead(path, 4, &size);
    if (!head || head->size() < 4) return false;
    uint32_t magic = 0;
    std::memcpy(&magic, head->data(), 4);
    return magic == kMagic;
}

Result<TilePart> bakeTilePart(const Scene& scene, const SceneSpec& spec, StaticMethod method, uint32_t res,
                              uint32_t tile, uint32_t light, ShardId id, BakeRenderer renderer,
                              uint64_t build, const std::function<void(double)>& progress) {
    if (!isMhFamily(method)) return fail("tile shards build mh, mmh or dagmh");
    if (light >= scene.lights.size()) return fail("light " + std::to_string(light) + " is not in the scene");
    if (std::string why = bakeSkipReason(scene, scene.lights[light]); !why.empty())
        return fail("light " + std::to_string(light) + " cannot be baked: " + why);
    const std::vector<LightFrustum> frusta = bakeFrustums(scene, scene.lights[light]);
    if (frusta.size() != 1) return fail("tile shards take a spot or directional light (one map)");
    auto grid = mhTileGrid(res, tile);
    if (!grid) return fail(grid.error());
    TilePart p;
    p.shard = id, p.method = method, p.resolution = res, p.tile = grid->tile, p.light = light, p.face = 0;
    p.renderer = renderer, p.scene = spec, p.frustum = frusta[0], p.build = build;
    p.fingerprint = sceneFingerprint(scene);
    const CasterTriangles casters = castersFromScene(scene);
    const DualRasterizer raster(casters, p.frustum, res);
    DualTileSource source = [&raster](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* enter,
                                      uint32_t* exit, uint32_t* plane) -> Result<void> {
        raster.renderRect(x0, y0, w, h, enter, exit, plane);
        return {};
    };
    MhTiledOptions o;
    o.tile = grid->tile, o.progress = progress;
    if (method == StaticMethod::DAGMH) o.planes = raster.planes(), p.planes = raster.planes();
    o.emptyBlock = [&raster](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
        return raster.blockEmpty(x0, y0, w, h);
    };
    std::vector<MhTile> tiles;
    if (auto r = buildMhTiles(
            *grid, source, o, [&](uint32_t k) { return k % id.count == id.index; }, tiles);
        !r)
        return fail(r.error());
    for (uint32_t k = 0; k < grid->count(); ++k)
        if (tiles[k].built) p.tiles.push_back({k, std::move(tiles[k])});
    return p;
}

Result<BakeFile> mergeTileParts(std::vector<TilePart>&& parts, const std::vector<std::string>& names) {
    if (parts.empty()) return fail("no tile parts to merge");
    const TilePart& a = parts[0];
    std::vector<int32_t> ownerOf(a.shard.count, -1);
    for (size_t i = 0; i < parts.size(); ++i) {
        const TilePart& b = parts[i];
        auto differ = [&](const std::string& what) {
            return fail(names[0] + " and " + names[i] + " are not tile parts of one bake: their " + what +
                        " differ");
        };
        if (b.scene.scene != a.scene.scene || b.scene.lights != a.scene.lights ||
            b.scene.seed != a.scene.seed)
            return differ("scenes");
        if (b.fingerprint != a.fingerprint) return differ("scene geometry (fingerprints)");
        if (b.build != a.build) return differ("manylights builds");
        if (b.method != a.method || b.resolution != a.resolution || b.tile != a.tile)
            return differ("method, resolution or tile");
        if (b.light != a.light || b.face != a.face ||
            std::memcmp(&b.frustum, &a.frustum, sizeof(LightFrustum)) != 0)
            return differ("lights or frustums");
        if (b.renderer != a.renderer) return differ("renderers");
        if (b.shard.count != a.shard.count) return differ("shard counts");
        if (ownerOf[b.shard.index] >= 0)
            return fail(names[size_t(ownerOf[b.shard.index])] + " and " + names[i] + " are both shard " +
                        std::to_string(b.shard.index) + "/" + std::to_string(b.shard.count));
        ownerOf[b.shard.index] = int32_t(i);
    }
    for (uint32_t s = 0; s < a.shard.count; ++s)
        if (ownerOf[s] < 0)
            return fail("shard " + std::to_string(s) + "/" + std::to_string(a.shard.count) + " is missing");
    auto grid = mhTileGrid(a.resolution, a.tile);
    if (!grid) return fail(grid.error());
    BakeFile file;
    file.scene = a.scene, file.renderer = a.renderer, file.method = a.method, file.resolution = a.resolution;
    const LightFrustum frustum = a.frustum;
    const uint32_t light = a.light, face = a.face;
    std::vector<MhTile> tiles(grid->count());
    for (TilePart& p : parts) {
        for (auto& [index, t] : p.tiles) tiles[index] = std::move(t);
        p.tiles.clear();
    }
    for (const TilePart& q : parts)
        if (q.planes != a.planes) return fail("the tile parts' depth planes differ");
    // A missing tile is a part that lost it: refused.
    auto tree = assembleMhTree(*grid, std::move(tiles), nullptr, a.planes);
    if (!tree) return fail(tree.error());
    Result<std::vector<uint32_t>> words = file.method == StaticMethod::MH    ? encodeMH(*tree)
                                          : file.method == StaticMethod::MMH ? encodeMMH(*tree)
                                                                             : encodeDAGMH(*tree);
    if (!words) return fail(words.error());
    file.records.push_back({light, face, file.method, file.resolution, frustum, std::move(words.value())});
    return file;
}

} // namespace ml
