// Tile shards on the command line (see apps/bake_tiles.h and bake/bake_tile_part.h).
#include "apps/bake_tiles.h"

#include "apps/commands.h"
#include "apps/json.h"
#include "io/safe_io.h"

#include <chrono>
#include <cstdio>
#include <fstream>

namespace ml {

Result<uint64_t> executableHash() {
    std::ifstream is("/proc/self/exe", std::ios::binary);
    if (!is) return fail("cannot read /proc/self/exe to identify this build");
    uint64_t h = fnv1a64(nullptr, 0);
    std::vector<char> buf(1 << 20);
    while (is.read(buf.data(), std::streamsize(buf.size())) || is.gcount() > 0)
        h = fnv1a64(buf.data(), size_t(is.gcount()), h);
    return h;
}

int bakeTileShard(const Scene& scene, const SceneSpec& spec, StaticMethod method, uint32_t res, uint32_t tile,
                  const std::vector<uint32_t>& selected, ShardId id, BakeRenderer renderer,
                  const std::string& out, bool quiet) {
    if (selected.size() != 1)
        return usageError("bake",
                          "--shard of a tiled bake splits one light's tiles: select exactly one light (" +
                              std::to_string(selected.size()) + " selected)");
    auto build = executableHash();
    if (!build) return runError("bake", build.error());
    const auto t0 = std::chrono::steady_clock::now();
    double last = 0;
    auto progress = [&](double f) {
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (quiet || s - last < 1.0) return;
        last = s;
        char left[48] = "";
        if (f >= 0.02 && f < 1.0) std::snprintf(left, sizeof(left), ", about %.0f s left", s * (1.0 - f) / f);
        std::fprintf(stderr, "manylights bake: [%3.0f%%] light %u, tiles of shard %u/%u %8.1f s%s\n",
                     100.0 * f, selected[0], id.index, id.count, s, left);
    };
    auto part =
        bakeTilePart(scene, spec, method, res, tile, selected[0], id, renderer, build.value(), progress);
    if (!part) return runError("bake", part.error());
    uint64_t nodes = 0;
    for (const auto& [index, t] : part->tiles) nodes += t.nodes.size();
    if (auto w = writeTilePart(out, part.value()); !w) return runError("bake", w.error());
    std::printf("wrote tile part %s: light %u, shard %u/%u, %zu tiles, %llu tree nodes\n",
                io::escapeText(out).c_str(), selected[0], id.index, id.count, part->tiles.size(),
                (unsigned long long)nodes);
    return 0;
}

int inspectTilePart(const std::string& path, bool asJson) {
    auto part = readTilePart(path);
    if (!part) return inputError("inspect", part.error());
    const TilePart& p = part.value();
    uint64_t nodes = 0;
    for (const auto& [index, t] : p.tiles) nodes += t.nodes.size();
    auto grid = mhTileGrid(p.resolution, p.tile);
    const uint32_t total = grid ? grid->count() : 0;
    if (asJson) {
        json::Object o;
        o.text("part", "tiles")
            .text("method", staticMethodName(p.method))
            .integer("resolution", p.resolution);
        o.integer("tile", p.tile).integer("light", p.light).integer("shard", p.shard.index);
        o.integer("shards", p.shard.count).integer("tiles", p.tiles.size()).integer("tiles_total", total);
        o.integer("tree_nodes", nodes).text("scene", p.scene.scene).integer("scene_lights", p.scene.lights);
        o.integer("seed", p.scene.seed);
        std::printf("%s\n", o.str().c_str());
        return 0;
    }
    std::printf(
        "%s: tile part %u/%u of light %u (%s at %u^2, %u^2 tiles): %zu of %u tiles, %llu tree nodes; scene "
        "%s, %u lights, seed %u; `manylights merge` of all %u parts makes the bake file\n",
        io::escapeText(path).c_str(), p.shard.index, p.shard.count, p.light, staticMethodName(p.method),
        p.resolution, p.tile, p.tiles.size(), total, (unsigned long long)nodes,
        io::escapeText(p.scene.scene).c_str(), p.scene.lights, p.scene.seed, p.shard.count);
    return 0;
}

int mergeTileShards(const std::vector<std::string>& paths, const std::string& out, bool quiet) {
    std::vector<TilePart> parts;
    for (const std::string& p : paths) {
        if (!isTilePartFile(p))
            return inputError("merge", p + ": not a tile part, while " + paths[0] + " is one");
        auto part = readTilePart(p);
        if (!part) return inputError("merge", part.error());
        parts.push_back(std::move(part.value()));
    }
    const size_t count = parts.size();
    auto file = mergeTileParts(std::move(parts), paths);
    if (!file) return inputError("merge", file.error());
    if (auto w = writeBakeFile(out, file.value()); !w) return runError("merge", w.error());
    if (!quiet)
        std::printf("manylights merge: %zu tile parts, light %u at %u^2 -> %s, %llu bytes\n", count,
                    file->records[0].light, file->resolution, io::escapeText(out).c_str(),
                    (unsigned long long)bakeFileBytes(file.value()).total());
    return 0;
}

} // namespace ml
