// A seeded mutation fuzzer for the two readers of untrusted files, without clang / libFuzzer:
//
//   fuzz_inputs bake|gltf [--seconds S] [--iterations N] [--seed X] [--dump-at I --dump-dir DIR] [--verbose]
//
// bake: the bake-file reader and every method's validator (SM, MH, MMH, DAG-MH, CPVS). Seeds are the
//       hostile tests' synthetic bake files (tests/hostile/hostile_util.h). Most mutants get their
//       checksums recomputed (file header, record, data, and the format's own) so that mutations reach
//       the structural checks behind the checksums; an accepted file is then looked up at every texel
//       (depth methods) or voxel column (CPVS) and its byte breakdown computed: under ASan/UBSan any
//       read outside the buffers is a crash.
// gltf: the glTF loader on .gltf and .glb mutants (tetrahedron with a data URI, a GLB with a BIN chunk,
//       an external buffer in a subfolder, punctual lights), with JSON tokens and hostile URIs spliced in.
//
// Mutations: bit flips, interesting bytes / words, truncation, insertion of random bytes or dictionary
// tokens, deletion, duplication, splices from another corpus entry. Mutants the reader accepts join the
// corpus. A finding is a crash (the process dies: ctest fails), a hang (ctest's timeout), or an error
// message that is not one clean line (printed, exit 1). Deterministic for a seed: a crash at iteration
// I is reproduced with --iterations I+1 and dumped with --dump-at I.
#include "../hostile/hostile_util.h"

#include "io/safe_io.h"
#include "scenes/scenes.h"

#include <algorithm>
#include <cctype>
#include <csignal>
#include <cstdio>
#include <chrono>
#include <map>
#include <cstring>
#include <iostream>
#include <random>

// The iteration in progress, for the crash message (a plain global: read from a signal handler).
volatile uint64_t gIteration = 0;
const char* gTarget = "";

extern "C" void __sanitizer_set_death_callback(void (*)(void)) __attribute__((weak));

namespace ml {
namespace {

using Bytes = std::string;

void sayIteration() {
    char buf[160];
    const int n = std::snprintf(
        buf, sizeof buf, "fuzz %s: crashed at iteration %llu (dump it: --dump-at %llu --dump-dir DIR)\n",
        gTarget, (unsigned long long)gIteration, (unsigned long long)gIteration);
    if (n > 0) (void)!::write(2, buf, size_t(n));
}
void onCrash(int sig) {
    sayIteration();
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}
void installCrashReport() {
    for (int sig : {SIGSEGV, SIGABRT, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, onCrash);
    if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(sayIteration);
}

struct Options {
    std::string target;
    double seconds = 5.0;
    uint64_t iterations = UINT64_MAX, seed = 1, dumpAt = UINT64_MAX;
    std::string dumpDir = ".";
    bool verbose = false; // print the most frequent rejection reasons (digits removed)
};

class Mutator {
  public:
    explicit Mutator(uint64_t seed) : rng_(seed) {}
    uint32_t below(uint32_t n) { return n ? uint32_t(rng_() % n) : 0; }
    bool chance(uint32_t percent) { return below(100) < percent; }

    // One to four mutations of `b`; `other` is for splices; `tokens` is a dictionary.
    void mutate(Bytes& b, const Bytes& other, const std::vector<std::string>& tokens, bool words) {
        const uint32_t n = 1 + below(4);
        for (uint32_t k = 0; k < n; ++k) {
            if (b.empty()) b = "x";
            const uint32_t at = below(uint32_t(b.size()));
            switch (below(9)) {
            case 0: // bit flip
                b[at] = char(b[at] ^ (1 << below(8)));
                break;
            case 1: { // interesting byte
                static const uint8_t v[] = {0, 1, 0x7F, 0x80, 0xFF, '0', '9', '"', '[', '{', '-', '.'};
                b[at] = char(v[below(sizeof v)]);
                break;
            }
            case 2: { // interesting word (aligned for bake files)
                static const uint32_t v[] = {
                    0,  1,  2,  3,  4,          5,           6,           15,          16,        31,
                    32, 63, 64, 65, 0x7FFFFFFF, 0x80000000u, 0xFFFFFFFFu, 0xFFFFFFFEu, 0xFFFFFFu, 0x1000000u};
                const size_t p = words ? (at & ~size_t(3)) : at;
                uint32_t x = v[below(sizeof v / 4)];
                if (chance(30)) { // small change of the word already there
                    std::memcpy(&x, b.data() + std::min(p, b.size() >= 4 ? b.size() - 4 : 0),
                                std::min<size_t>(4, b.size()));
                    x += uint32_t(int32_t(below(17)) - 8);
                }
                if (p + 4 <= b.size()) std::memcpy(&b[p], &x, 4);
                break;
            }
            case 3: // truncate
                b.resize(words && chance(70) ? (at & ~size_t(3)) : at);
                break;
            case 4: { // insert random bytes (whole words for bake files)
                Bytes ins(words ? 4 * (1 + below(4)) : 1 + below(8), '\0');
                for (char& c : ins) c = char(rng_());
                b.insert(words ? (at & ~size_t(3)) : at, ins);
                break;
            }
            case 5: // insert a token
                if (!tokens.empty()) b.insert(at, tokens[below(uint32_t(tokens.size()))]);
                break;
            case 6: { // delete a range
                const size_t len =
                    std::min<size_t>(b.size() - at, words ? 4 * (1 + below(8)) : 1 + below(32));
                b.erase(words ? (at & ~size_t(3)) : at, len);
                break;
            }
            case 7: { // duplicate a range
                const size_t len = std::min<size_t>(b.size() - at, 1 + below(64));
                b.insert(below(uint32_t(b.size())), b.substr(at, len));
                break;
            }
            case 8: { // splice: our head, the other's tail
                if (other.empty()) break;
                const size_t from = below(uint32_t(other.size()));
                b = b.substr(0, at) + other.substr(from);
                break;
            }
            }
        }
    }

  private:
    std::mt19937_64 rng_;
};

// A finding that is not a crash: an error that is not one printable line.
bool badMessage(const std::string& e) {
    if (e.empty()) return true;
    for (unsigned char c : e)
        if (c < 0x20 || c == 0x7F) return true;
    return e.size() > 4096;
}

// ---- bake files ----

uint32_t formatChecksumWord(uint32_t method) {
    switch (StaticMethod(method)) {
    case StaticMethod::SM:
        return smfmt::kChecksum;
    case StaticMethod::MH:
    case StaticMethod::MMH:
        return mhfmt::kChecksum;
    case StaticMethod::DAGMH:
        return dagfmt::kChecksum;
    case StaticMethod::CPVS:
        return kCpvsHChecksum;
    default:
        return UINT32_MAX;
    }
}

// Recomputes every checksum the mutant's own (possibly broken) layout points at.
void fixChecksums(Bytes& b, Mutator& m) {
    const size_t count = b.size() / 4;
    if (count < bakefmt::kFixedHeaderWords) return;
    std::vector<uint32_t> w(count);
    std::memcpy(w.data(), b.data(), count * 4);
    using namespace bakefmt;
    if (m.chance(90)) w[kHTotalLo] = uint32_t(count), w[kHTotalHi] = 0;
    const uint64_t headerWords = kFixedHeaderWords + (uint64_t(w[kHSceneBytes]) + 3) / 4;
    for (uint64_t r = 0; r < w[kHRecordCount] && r < 4096; ++r) {
        const uint64_t at = headerWords + r * kRecordWords;
        if (at + kRecordWords > count) break;
        uint32_t* rec = &w[size_t(at)];
        const uint64_t offset = uint64_t(rec[kROffsetLo]) | uint64_t(rec[kROffsetHi]) << 32;
        const uint64_t words = uint64_t(rec[kRWordsLo]) | uint64_t(rec[kRWordsHi]) << 32;
        if (offset <= count && words <= count - offset && words > 0) {
            uint32_t* data = &w[size_t(offset)];
            const uint32_t cw = formatChecksumWord(w[kHMethod]);
            if (cw < words) {
                data[cw] = w[kHMethod] == uint32_t(StaticMethod::CPVS)
                               ? cpvsChecksum(data, size_t(words))
                               : stat::checksumWords(data, size_t(words), cw);
            }
            rec[kRDataChecksum] = stat::checksumWords(data, size_t(words), SIZE_MAX);
        }
        rec[kRChecksum] = stat::checksumWords(rec, kRecordWords, kRChecksum);
    }
    if (headerWords <= count) w[kHChecksum] = stat::checksumWords(w.data(), size_t(headerWords), kHChecksum);
    std::memcpy(b.data(), w.data(), count * 4);
}

// Everything a reader of an accepted file may do with it (inspect, the lookups, the upload).
uint64_t exercise(const BakeFile& f) {
    uint64_t sum = bakeFileBytes(f).total();
    for (const BakeRecord& r : f.records) {
        const uint32_t res = staticResolution(r.method, r.data.data());
        if (isDepthMethod(r.method)) {
            for (uint32_t y = 0; y < res; ++y)
                for (uint32_t x = 0; x < res; ++x) sum += lookupStaticDepth(r.method, r.data.data(), 0, x, y);
        } else if (r.method == StaticMethod::CPVS) {
            for (int32_t y = 0; y < int32_t(res); y += 3)
                for (int32_t x = 0; x < int32_t(res); x += 3)
                    for (int32_t s = 0; s < int32_t(res); s += 7)
                        sum += cpvsShadowedVoxel(r.data.data(), 0, x, y, s);
        }
    }
    return sum;
}

std::vector<Bytes> bakeSeeds() {
    std::vector<Bytes> seeds;
    for (StaticMethod m :
         {StaticMethod::SM, StaticMethod::MH, StaticMethod::MMH, StaticMethod::DAGMH, StaticMethod::CPVS})
        for (uint32_t records : {1u, 2u}) {
            auto words = serializeBakeFile(hostile::syntheticBake(m, records, records * 7));
            if (!words) {
                std::cerr << "fuzz: cannot build a seed: " << words.error() << "\n";
                std::exit(2);
            }
            seeds.emplace_back(reinterpret_cast<const char*>(words->data()), words->size() * 4);
        }
    // Version 2 (resolution from need): a need block with an entry per record and one unbaked light.
    for (StaticMethod m : {StaticMethod::DAGMH, StaticMethod::CPVS}) {
        BakeFile f = hostile::syntheticBake(m, 2, 3);
        f.hasNeed = true;
        f.need.region = "path:drive, 8 samples over 4 s";
        f.need.width = 320, f.need.height = 180, f.need.minRes = 64, f.need.maxRes = 64, f.need.samples = 8;
        f.need.lights.push_back({0, 0, NeedReason::NoCaster});
        for (const BakeRecord& r : f.records)
            f.need.lights.push_back({r.light, 64, NeedReason::Capped, 5.0f, 3, 200.0f, 40, 30});
        auto words = serializeBakeFile(f);
        if (!words) {
            std::cerr << "fuzz: cannot build a need seed: " << words.error() << "\n";
            std::exit(2);
        }
        seeds.emplace_back(reinterpret_cast<const char*>(words->data()), words->size() * 4);
    }
    return seeds;
}

// ---- glTF ----

struct GltfSeed {
    Bytes bytes;
    bool binary;
};

std::vector<GltfSeed> gltfSeeds(const std::filesystem::path& dir) {
    std::filesystem::create_directories(dir / "scene" / "sub");
    hostile::writeBytes((dir / "scene" / "sub" / "tetra.bin").string(), hostile::tetraBin());
    hostile::writeBytes((dir / "secret.bin").string(), hostile::tetraBin());
    const std::string lights =
        R"("extensionsUsed": ["KHR_lights_punctual"], "extensions": {"KHR_lights_punctual": {"lights": [)"
        R"({"type": "spot", "intensity": 3, "range": 5, "spot": {"outerConeAngle": 0.6}}, {"type": "point"}]}}, )";
    return {
        {hostile::tetraJson(hostile::dataUri(hostile::tetraBin())), false},
        {hostile::tetraJson("\"uri\": \"sub/tetra.bin\""), false},
        {hostile::tetraJson(hostile::dataUri(hostile::tetraBin()), lights,
                            R"(, "extensions": {"KHR_lights_punctual": {"light": 0}}, "children": [])"),
         false},
        {hostile::glb(hostile::tetraJson(""), hostile::tetraBin()), true},
        {hostile::glb(hostile::tetraJson("", "\"extras\": {\"a\": [[1, {\"b\": null}]]}, "),
                      hostile::tetraBin()),
         true},
    };
}

const std::vector<std::string> kJsonTokens = {"[",
                                              "]",
                                              "{",
                                              "}",
                                              "\"",
                                              ",",
                                              ":",
                                              "-1",
                                              "0",
                                              "4294967295",
                                              "2147483648",
                                              "1e308",
                                              "-1e308",
                                              "null",
                                              "true",
                                              "1.5707963267948966",
                                              "\"uri\": \"../secret.bin\"",
                                              "\"uri\": \"/etc/passwd\"",
                                              "\"data:,\"",
                                              "\"byteStride\": 4",
                                              "\"count\": 99999999",
                                              "\"bufferView\": 1",
                                              "\"byteOffset\": 70",
                                              "\"mode\": 0",
                                              "\"children\": [0]",
                                              "\"matrix\": [0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]",
                                              "\"indices\": 0",
                                              "\\u0000",
                                              "\\\"",
                                              "\x1b[2J",
                                              "\n",
                                              "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[",
                                              "\"sparse\": {\"count\": 1}",
                                              "\"scale\": [0, 0, 0]",
                                              "\"rotation\": [0, 0, 0, 0]",
                                              "\"range\": -1",
                                              "\"type\": \"spot\""};

// After a mutation of a .glb, sometimes repair the lengths so the mutant gets past the header check.
void fixGlb(Bytes& b, Mutator& m) {
    if (b.size() < 20 || !m.chance(60)) return;
    const uint32_t total = uint32_t(b.size());
    std::memcpy(&b[8], &total, 4);
    if (m.chance(50)) {
        // The JSON chunk runs to the first "BIN\0" tag (or the end).
        const size_t bin = b.find(std::string("BIN\0", 4), 20);
        uint32_t json = uint32_t((bin == std::string::npos ? b.size() : bin - 4) - 20);
        std::memcpy(&b[12], &json, 4);
        if (bin != std::string::npos) {
            uint32_t binLen = uint32_t(b.size() - bin - 4);
            std::memcpy(&b[bin - 4], &binLen, 4);
        }
    }
}

// ---- the loop ----

int run(const Options& o) {
    const auto start = std::chrono::steady_clock::now();
    const std::filesystem::path dir = hostile::tempDir();
    Mutator m(o.seed);
    std::vector<Bytes> corpus;
    std::vector<bool> binary;
    if (o.target == "bake") {
        corpus = bakeSeeds();
        binary.assign(corpus.size(), true);
    } else {
        for (const GltfSeed& s : gltfSeeds(dir)) corpus.push_back(s.bytes), binary.push_back(s.binary);
    }
    const size_t seeds = corpus.size();
    uint64_t it = 0, accepted = 0, rejected = 0;
    std::map<std::string, uint64_t> reasons;
    const std::string gltfPath = (dir / "scene" / "fuzz.gltf").string(),
                      glbPath = (dir / "scene" / "fuzz.glb").string();
    gTarget = o.target.c_str();
    installCrashReport();
    for (; it < o.iterations; ++it) {
        gIteration = it;
        if ((it & 15) == 0 &&
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > o.seconds)
            break;
        const size_t pick = m.below(uint32_t(corpus.size()));
        Bytes input = corpus[pick];
        const Bytes& other = corpus[m.below(uint32_t(corpus.size()))];
        m.mutate(input, other, o.target == "bake" ? std::vector<std::string>{} : kJsonTokens,
                 o.target == "bake");
        if (o.target == "bake" && m.chance(85)) fixChecksums(input, m);
        if (o.target == "gltf" && binary[pick]) fixGlb(input, m);
        if (it == o.dumpAt) {
            const std::string p = o.dumpDir + "/fuzz_" + o.target + "_" + std::to_string(it) +
                                  (o.target == "bake" ? ".mlbk"
                                   : binary[pick]     ? ".glb"
                                                      : ".gltf");
            hostile::writeBytes(p, input);
            std::cout << "fuzz " << o.target << ": iteration " << it << " written to " << p << "\n";
            return 0;
        }
        std::string error;
        bool ok = false;
        if (o.target == "bake") {
            std::vector<uint32_t> words(input.size() / 4);
            if (!words.empty()) std::memcpy(words.data(), input.data(), words.size() * 4);
            auto f = parseBakeFile("fuzz.mlbk", words.data(), words.size());
            if (f) {
                ok = true;
                volatile uint64_t sink = exercise(f.value());
                (void)sink;
            } else {
                error = f.error();
            }
            if ((it & 255) == 0) { // now and then through the file reader too
                const std::string p = (dir / "fuzz.mlbk").string();
                hostile::writeBytes(p, input);
                auto r = readBakeFile(p);
                if (!r && badMessage(r.error())) error = r.error(), ok = false;
            }
        } else {
            const std::string& p = binary[pick] ? glbPath : gltfPath;
            hostile::writeBytes(p, input);
            auto s = loadGltf(p, 4, 1);
            if (s) {
                ok = true;
                for (const Light& l : s->lights)
                    if (!(l.range > 0.0f) ||
                        (l.type == LightKind::Spot && !(l.outerAngle > 0.0f && l.outerAngle < 1.5707964f)))
                        error = "accepted a light out of range";
            } else {
                error = s.error();
            }
        }
        if ((!ok || !error.empty()) && badMessage(error)) {
            std::cout << "fuzz " << o.target << ": FINDING at iteration " << it << " (seed " << o.seed
                      << "): message is not one clean line: " << io::escapeText(error, 400) << "\n";
            return 1;
        }
        if (ok && error.empty()) {
            ++accepted;
            if (corpus.size() < seeds + 256 && input != corpus[pick]) {
                corpus.push_back(input);
                binary.push_back(binary[pick]);
            }
        } else if (!ok) {
            ++rejected;
            if (o.verbose) {
                std::string k;
                for (char c : error.substr(error.find(':') + 1))
                    if (!std::isdigit(static_cast<unsigned char>(c))) k += c;
                ++reasons[k.substr(0, 90)];
            }
        } else {
            std::cout << "fuzz " << o.target << ": FINDING at iteration " << it << ": " << error << "\n";
            return 1;
        }
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "fuzz " << o.target << ": " << it << " iterations in " << s << " s (seed " << o.seed
              << "): " << accepted << " accepted, " << rejected << " rejected with one-line errors, corpus "
              << corpus.size() << ", 0 findings\n";
    std::vector<std::pair<uint64_t, std::string>> top;
    for (const auto& [k, n] : reasons) top.push_back({n, k});
    std::sort(top.rbegin(), top.rend());
    for (size_t i = 0; i < top.size() && i < 40; ++i)
        std::cout << "  " << top[i].first << " " << top[i].second << "\n";
    return 0;
}

} // namespace
} // namespace ml

int main(int argc, char** argv) {
    ml::Options o;
    auto usage = [] {
        std::cerr << "usage: fuzz_inputs bake|gltf [--seconds S] [--iterations N] [--seed X] "
                     "[--dump-at I --dump-dir DIR] [--verbose]\n";
        return 2;
    };
    if (argc < 2) return usage();
    o.target = argv[1];
    if (o.target != "bake" && o.target != "gltf") return usage();
    int last = argc;
    if (std::string(argv[argc - 1]) == "--verbose") o.verbose = true, --last;
    for (int i = 2; i + 1 < last; i += 2) {
        const std::string f = argv[i], v = argv[i + 1];
        if (f == "--seconds")
            o.seconds = std::stod(v);
        else if (f == "--iterations")
            o.iterations = std::stoull(v);
        else if (f == "--seed")
            o.seed = std::stoull(v);
        else if (f == "--dump-at")
            o.dumpAt = std::stoull(v);
        else if (f == "--dump-dir")
            o.dumpDir = v;
        else
            return usage();
    }
    if (last % 2 != 0) return usage();
    return ml::run(o);
}
