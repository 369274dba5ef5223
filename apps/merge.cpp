// `manylights merge`: the parts of a sharded bake (bake --shard I/N) -> the one bake file a single
// process would have written for the same lights, byte for byte. Everything is checked before anything
// is written: each part on its own (checksums, bake_shard.h), then the parts together (one scene, method,
// resolution, renderer, device, build, selection and N; every selected light in exactly one part).
// Tile parts of one light (bake/bake_tile_part.h) go to mergeTileShards (apps/bake_tiles.h).
#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/bake_tiles.h"
#include "bake/bake_shard.h"

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace ml {

namespace {

const char* kMergeHelp = R"(usage: manylights merge PART... --out FILE [--quiet]
Merges the parts of a sharded bake (manylights bake ... --shard I/N) into one bake file, identical byte
for byte to the bake file of one `manylights bake` of the same lights. Refused, with one line and exit
status 2, when a part is damaged, when the parts differ in scene (name, light count, seed or geometry),
method, resolution, renderer, device or manylights build, or when a selected light is in no part or in
two. Parts may be given in any order (e.g. a shell glob).
Tile parts (bake --shard I/N of one light's tiles) merge the same way into the bake file of one tiled
bake, byte for byte: refused when they differ in scene, geometry, build, method, resolution, light or
shard count, or when a shard or a tile is missing.
  --out FILE   the bake file to write
  --quiet      no summary line on stdout
)";

} // namespace

int runMerge(int argc, char** argv) {
    std::vector<std::string> paths;
    std::vector<char*> rest = {argv[0], argv[1]};
    for (int i = 2; i < argc; ++i) {
        std::string s = argv[i];
        if (s == "--out") { // the one valued flag: keep its value with it
            rest.push_back(argv[i]);
            if (i + 1 < argc) rest.push_back(argv[++i]);
        } else if (!s.empty() && s[0] == '-') {
            rest.push_back(argv[i]);
        } else {
            paths.push_back(s);
        }
    }
    auto args = cli::parse(int(rest.size()), rest.data(), 2, {"--out"}, {"--quiet"});
    if (!args) return usageError("merge", args.error());
    if (args->help) {
        std::fputs(kMergeHelp, stdout);
        return 0;
    }
    if (paths.empty()) return usageError("merge", "no PART files (see --help)");
    const std::string out = args->get("--out", "");
    if (!args->has("--out") || out.empty()) return usageError("merge", "--out: required (see --help)");
    const std::filesystem::path outDir = std::filesystem::absolute(out).parent_path();
    if (!std::filesystem::is_directory(outDir))
        return usageError("merge", "--out: " + outDir.string() + " is not a directory");

    if (isTilePartFile(paths[0])) return mergeTileShards(paths, out, args->has("--quiet"));
    std::vector<BakePart> parts;
    for (const std::string& p : paths) {
        auto part = readBakePart(p);
        if (!part) return inputError("merge", part.error());
        parts.push_back(std::move(part.value()));
    }
    auto merged = mergeBakeParts(parts, paths);
    if (!merged) return inputError("merge", merged.error());
    if (auto w = writeBakeFile(out, merged.value()); !w) return runError("merge", w.error());
    if (!args->has("--quiet")) {
        const BakeBytes b = bakeFileBytes(merged.value());
        std::printf("manylights merge: %zu parts (%u shards), %zu selected lights, %zu records -> %s, %llu "
                    "bytes\n",
                    parts.size(), parts[0].shard.count, parts[0].selected.size(), merged->records.size(),
                    out.c_str(), (unsigned long long)b.total());
    }
    return 0;
}

} // namespace ml
