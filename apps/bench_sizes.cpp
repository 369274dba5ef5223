// `manylights bench sizes`: MH, MMH and DAG-MH bytes on real dual depth maps (CPU rasteriser) at the sizes
// the papers compare (4K^2, 8K^2 and above): overviews of night-city and sample-building and a few of their
// spotlights, with the target ratios (MMH <= 0.85 MH, DAG-MH <= 0.75 MMH), encode times and the
// DAG-MH byte breakdown. Tens of seconds per map, so it is a command and not a ctest; the ctest runs it at
// 256^2. Every DAG-MH value is checked against its MH node's interval (dagmhCheckValues), and every texel
// of the three encodings against the map when the map was rendered in this run. Prints a table, writes
// DIR/bench_sizes.csv; the last stdout line is JSON.
#include "apps/cli.h"
#include "apps/commands.h"
#include "apps/json.h"
#include "apps/options.h"
#include "bake/scene_casters.h"
#include "io/safe_io.h"
#include "scenes/scenes.h"
#include "shadows/static/dagmh.h"
#include "shadows/static/mh.h"
#include "shadows/static/mmh.h"
#include "shadows/static/raster_dual.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace ml {

static const char* kBenchSizesHelp = R"(usage: manylights bench sizes [options]
MH, MMH and DAG-MH bytes on real dual depth maps (CPU rasteriser), the ratios MMH/MH (goal <= 0.85) and
DAG-MH/MMH (goal <= 0.75), encode times and the DAG-MH breakdown.
  --res LIST       map resolutions (default 4096,8192; 16384 needs minutes and several GB)
  --cases LIST     from night-city-overview, night-city-spot0, night-city-spot1, sample-building-overview,
                   sample-building-spot0 (default: the night-city ones, and the sample-building ones
                   with --building)
  --building FILE  the sample-building glTF (e.g. ../shared/scenes/sample-building.gltf)
  --cache DIR      keep the MH trees in DIR (<case>_<res>.tree): reruns skip the rasteriser (and the
                   per-texel check, which needs the map)
  --out DIR        output folder for bench_sizes.csv (default out/bench_sizes)
Exits 1 when an encoding fails validation or decodes a value outside its interval; a method whose
encoder fails at a size says so in its columns.
Last stdout line: {"bench": "sizes", "maps": K, "mean_mmh_over_mh": ..., "mean_dagmh_over_mmh": ...,
"errors": ...}
)";

namespace {

struct Case {
    std::string name;
    bool building;
    int spot; // -1: an overview spotlight over the whole scene, else the scene's spotlight index
};

const Case kCases[] = {{"night-city-overview", false, -1},
                       {"night-city-spot0", false, 0},
                       {"night-city-spot1", false, 1},
                       {"sample-building-overview", true, -1},
                       {"sample-building-spot0", true, 0}};

struct Row {
    std::string name;
    uint32_t res = 0;
    double mh = NAN, mmh = NAN, dag = 0; // bytes; NaN: not encodable
    double rasterMs = NAN, mhMs = 0, mmhMs = 0, dagMs = 0;
    DagMhStats stats;
    stat::ByteBreakdown parts;
    std::string texels = "-"; // texels outside their interval, or "-" when the map came from the cache
    uint64_t errors = 0;
};

// One wide spotlight looking down at the scene's centre from outside its bounds: all of it in one map.
LightFrustum overview(const Scene& s) {
    const glm::vec3 c = (s.boundsMin + s.boundsMax) * 0.5f;
    const float r = glm::length(s.boundsMax - s.boundsMin) * 0.5f;
    Light l;
    l.direction = glm::normalize(glm::vec3(0.35f, -1.0f, 0.25f));
    l.position = c - l.direction * (r * 2.0f);
    l.outerAngle = std::asin(0.5f) * 1.05f;
    l.range = r * 3.2f;
    return spotLightFrustum(l);
}

// The cache holds the tree's resolution, levels and nodes as they are in memory: it is read back only
// by the same build of this command (a scratch file, not an exchange format).
bool loadTree(const std::string& path, MhTree& t) {
    std::ifstream f(path, std::ios::binary);
    uint64_t n = 0;
    f.read(reinterpret_cast<char*>(&t.resolution), 4).read(reinterpret_cast<char*>(&t.levels), 4);
    f.read(reinterpret_cast<char*>(&n), 8);
    if (!f || n > (uint64_t(1) << 36)) return false;
    t.nodes.resize(n);
    f.read(reinterpret_cast<char*>(t.nodes.data()), std::streamsize(n * sizeof(MhTree::Node)));
    return bool(f);
}

void saveTree(const std::string& path, const MhTree& t) {
    std::ofstream f(path, std::ios::binary);
    const uint64_t n = t.nodes.size();
    f.write(reinterpret_cast<const char*>(&t.resolution), 4)
        .write(reinterpret_cast<const char*>(&t.levels), 4);
    f.write(reinterpret_cast<const char*>(&n), 8);
    f.write(reinterpret_cast<const char*>(t.nodes.data()), std::streamsize(n * sizeof(MhTree::Node)));
}

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Texels whose decoded depth leaves [enter, exit] (an empty texel must decode to exactly kDepthEmpty).
uint64_t lossyTexels(const DualDepthMap& m, const std::vector<uint32_t>& data,
                     uint32_t (*lookup)(const uint32_t*, uint32_t, uint32_t)) {
    uint64_t bad = 0;
    for (uint32_t y = 0; y < m.resolution; ++y)
        for (uint32_t x = 0; x < m.resolution; ++x) {
            const size_t i = size_t(y) * m.resolution + x;
            const uint32_t v = lookup(data.data(), x, y), lo = m.enter[i];
            bad += lo == kDepthEmpty ? v != kDepthEmpty : (v < lo || v > std::max(lo, m.exit[i]));
        }
    return bad;
}

} // namespace

int runBenchSizes(int argc, char** argv) {
    auto args = cli::parse(argc, argv, 3, {"--res", "--cases", "--building", "--cache", "--out"}, {});
    if (!args) return usageError("bench sizes", args.error());
    if (args->help) {
        std::fputs(kBenchSizesHelp, stdout);
        return 0;
    }
    auto sizes = opts::uintList("--res", args->get("--res", "4096,8192"), 16, 16384);
    if (!sizes) return usageError("bench sizes", sizes.error());
    const std::string buildingFile = args->get("--building", "");
    std::vector<Case> cases;
    if (args->has("--cases")) {
        auto names = opts::splitList("--cases", args->get("--cases", ""));
        if (!names) return usageError("bench sizes", names.error());
        for (const std::string& item : names.value()) {
            const Case* found = nullptr;
            for (const Case& c : kCases)
                if (c.name == item) found = &c;
            if (!found) return usageError("bench sizes", "--cases: unknown case '" + item + "' (see --help)");
            if (found->building && buildingFile.empty())
                return usageError("bench sizes", "--cases: '" + item + "' needs --building FILE");
            cases.push_back(*found);
        }
    } else {
        for (const Case& c : kCases)
            if (!c.building || !buildingFile.empty()) cases.push_back(c);
    }
    const std::string cache = args->get("--cache", ""), out = args->get("--out", "out/bench_sizes");
    if (auto r = cli::checkOutputDirectory("--out", out); !r) return usageError("bench sizes", r.error());
    if (!cache.empty())
        if (auto r = cli::makeDirectory(cache); !r) return runError("bench sizes", r.error());

    Result<Scene> city = fail("not loaded"), building = fail("not loaded");
    std::vector<Row> rows;
    for (uint32_t res : sizes.value())
        for (const Case& c : cases) {
            Row row;
            row.name = c.name;
            row.res = res;
            const std::string file =
                cache.empty() ? "" : cache + "/" + c.name + "_" + std::to_string(res) + ".tree";
            MhTree tree;
            DualDepthMap map;
            if (file.empty() || !loadTree(file, tree)) {
                Result<Scene>& s = c.building ? building : city;
                if (!s) s = c.building ? loadScene(buildingFile, 8, 1) : loadScene("night-city", 256, 1);
                if (!s) return runError("bench sizes", s.error());
                LightFrustum fr = overview(*s);
                int k = 0;
                bool found = c.spot < 0;
                for (const Light& l : s->lights)
                    if (l.type == LightKind::Spot && c.spot >= 0 && k++ == c.spot)
                        fr = spotLightFrustum(l), found = true;
                if (!found) return runError("bench sizes", c.name + ": the scene has too few spotlights");
                const auto t0 = std::chrono::steady_clock::now();
                map = rasterizeDual(castersFromScene(*s), fr, res);
                row.rasterMs = msSince(t0);
                auto t = buildMhTree(map);
                if (!t) return runError("bench sizes", c.name + ": " + t.error());
                tree = std::move(*t);
                if (!file.empty()) saveTree(file, tree);
            }
            auto t0 = std::chrono::steady_clock::now();
            auto mh = encodeMH(tree);
            row.mhMs = msSince(t0);
            t0 = std::chrono::steady_clock::now();
            auto mmh = encodeMMH(tree);
            row.mmhMs = msSince(t0);
            t0 = std::chrono::steady_clock::now();
            auto dag = encodeDAGMH(tree, &row.stats);
            row.dagMs = msSince(t0);
            if (!dag) return runError("bench sizes", c.name + " " + std::to_string(res) + ": " + dag.error());
            row.dag = dag->size() * 4.0;
            row.errors += !validateDAGMH(dag->data(), dag->size()).ok();
            row.errors += dagmhCheckValues(tree, dag->data());
            if (mh) row.mh = mh->size() * 4.0, row.errors += !validateMH(mh->data(), mh->size()).ok();
            if (mmh) row.mmh = mmh->size() * 4.0, row.errors += !validateMMH(mmh->data(), mmh->size()).ok();
            if (!map.enter.empty() && row.errors == 0) {
                uint64_t lossy = lossyTexels(map, *dag, dagmhLookup);
                if (mh) lossy += lossyTexels(map, *mh, mhLookup);
                if (mmh) lossy += lossyTexels(map, *mmh, mmhLookup);
                row.texels = std::to_string(lossy);
                row.errors += lossy;
            }
            row.parts = breakdownDAGMH(dag->data(), dag->size());
            std::fprintf(stderr, "  %s %u: DAG-MH %.0f B in %.0f ms\n", c.name.c_str(), res, row.dag,
                         row.dagMs);
            rows.push_back(std::move(row));
        }

    std::printf("bench sizes: %zu maps (NaN: MH or MMH not encodable at that size)\n", rows.size());
    std::printf(
        "| case | res | SM B | MH B | MMH B | DAG-MH B | MMH/MH | DAG-MH/MMH | raster ms | MH ms | MMH ms | "
        "DAG-MH ms | skip B | nodes B | treelets B | chunks B | factors B | values with factors | "
        "bits/factor | raw chunks | lossy texels | errors |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|--"
                "-:|---:|---:|"
                "---:|\n");
    std::ostringstream csv;
    csv << "case,res,sm_bytes,mh_bytes,mmh_bytes,dagmh_bytes,raster_ms,mh_ms,mmh_ms,dagmh_ms,skip_bytes,node_"
           "bytes,"
           "treelet_bytes,chunk_bytes,factor_bytes,values,factors,factor_bits,raw_chunks,lossy_texels,"
           "errors\n";
    double mmhOverMh = 0, dagOverMmh = 0;
    int mhCount = 0, mmhCount = 0;
    uint64_t errors = 0;
    for (const Row& r : rows) {
        const DagMhStats& s = r.stats;
        const double sm = 4.0 * r.res * r.res; // the 32-bit dual depth map's enter plane
        std::printf(
            "| %s | %u | %.0f | %.0f | %.0f | %.0f | %.3f | %.3f | %.0f | %.0f | %.0f | %.0f | %llu | %llu | "
            "%llu | %llu | %llu | %.1f %% | %.2f | %llu | %s | %llu |\n",
            r.name.c_str(), r.res, sm, r.mh, r.mmh, r.dag, r.mmh / r.mh, r.dag / r.mmh, r.rasterMs, r.mhMs,
            r.mmhMs, r.dagMs, (unsigned long long)r.parts.skipList, (unsigned long long)r.parts.nodes,
            (unsigned long long)r.parts.treelets, (unsigned long long)r.parts.values,
            (unsigned long long)r.parts.factors,
            s.values ? 100.0 * double(s.factors) / double(s.values) : 0.0,
            s.factors ? double(s.factorBits) / double(s.factors) : 0.0, (unsigned long long)s.rawChunks,
            r.texels.c_str(), (unsigned long long)r.errors);
        csv << r.name << "," << r.res << "," << sm << "," << r.mh << "," << r.mmh << "," << r.dag << ","
            << r.rasterMs << "," << r.mhMs << "," << r.mmhMs << "," << r.dagMs << "," << r.parts.skipList
            << "," << r.parts.nodes << "," << r.parts.treelets << "," << r.parts.values << ","
            << r.parts.factors << "," << s.values << "," << s.factors << "," << s.factorBits << ","
            << s.rawChunks << "," << r.texels << "," << r.errors << "\n";
        if (!std::isnan(r.mh) && !std::isnan(r.mmh)) mmhOverMh += r.mmh / r.mh, ++mhCount;
        if (!std::isnan(r.mmh)) dagOverMmh += r.dag / r.mmh, ++mmhCount;
        errors += r.errors;
    }
    const double meanMmh = mhCount ? mmhOverMh / mhCount : NAN,
                 meanDag = mmhCount ? dagOverMmh / mmhCount : NAN;
    std::printf(
        "mean MMH/MH %.3f (goal <= 0.85) over %d maps, mean DAG-MH/MMH %.3f (goal <= 0.75) over %d maps\n",
        meanMmh, mhCount, meanDag, mmhCount);
    if (auto r = cli::makeDirectory(out); !r) return runError("bench sizes", r.error());
    if (auto w = io::writeFileAtomically(out + "/bench_sizes.csv", csv.str()); !w)
        return runError("bench sizes", w.error());
    std::printf("wrote %s/bench_sizes.csv\n", out.c_str());
    // JSON has no NaN: a mean over no map is null.
    auto mean = [](double v) { return std::isnan(v) ? std::string("null") : json::number(v); };
    json::Object summary;
    summary.text("bench", "sizes").integer("maps", rows.size());
    summary.raw("mean_mmh_over_mh", mean(meanMmh)).raw("mean_dagmh_over_mmh", mean(meanDag));
    summary.integer("errors", errors);
    std::printf("%s\n", summary.str().c_str());
    return errors == 0 ? 0 : 1;
}

} // namespace ml
