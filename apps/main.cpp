// manylights: the command line. `manylights help` lists the subcommands.
#include "apps/commands.h"
#include "io/safe_io.h"

#include <cstdio>
#include <cstring>

namespace ml {
// Messages can carry text from files (scene names, paths inside a bake file, parser messages):
// escaped here, once for every command, so they stay one line without terminal codes.
namespace {
int say(const char* command, const std::string& message, int status) {
    std::fprintf(stderr, "manylights %s: %s\n", command, io::escapeText(message, 1000).c_str());
    return status;
}
} // namespace
int usageError(const char* command, const std::string& message) {
    return say(command, message, kExitUsage);
}
int inputError(const char* command, const std::string& message) {
    return say(command, message, kExitInput);
}
int runError(const char* command, const std::string& message) {
    return say(command, message, kExitRun);
}
std::optional<cli::Args> commandArgs(const char* command, const char* help, Result<cli::Args> args,
                                     int& status) {
    if (!args) {
        status = usageError(command, args.error());
        return std::nullopt;
    }
    if (args->help) {
        std::fputs(help, stdout);
        status = 0;
        return std::nullopt;
    }
    return std::move(args.value());
}
} // namespace ml

static const char* kHelp = R"(usage: manylights <command> [options]
Many shadowed lights on Vulkan. Commands (each takes --help):
  demo    render the night city (or a glTF scene) headless; images, GPU profile and stats
  bench   benchmarks: `bench culling`, `static`, `vsm`, `vsm-rays`, `flicker`, `cpvs`, `sizes`, `cpu`,
          `record`, `soak`
  bake    bake static lights' shadows (spot, point, directional; sm, mh, mmh, dagmh, cpvs) into one file
  inspect validate a bake file and report its method, resolution, lights and bytes per part
  verify  re-render a bake file's lights and check every texel or voxel (last line JSON)
  check   `check vsm`: every virtual-shadow-map lookup of a camera path against full reference maps
  merge   merge the parts of a sharded bake (bake --shard I/N) into one bake file
Exit status (every command): 0 done; 1 usage error (a bad, missing, repeated or useless option, a
value out of range, or settings past this machine's device limits or --max-memory: refused before
any work, but a tiled bake goes on held to --max-memory); 2 a hostile or malformed input file (scene, bake file, part); 3 the run failed (device
error, output not written, validation messages, or a check that found mismatches).
)";

int main(int argc, char** argv) {
    if (argc < 2 || !std::strcmp(argv[1], "help") || !std::strcmp(argv[1], "--help") ||
        !std::strcmp(argv[1], "-h")) {
        std::fputs(kHelp, argc < 2 ? stderr : stdout);
        return argc < 2 ? ml::kExitUsage : 0;
    }
    if (!std::strcmp(argv[1], "demo")) return ml::runDemo(argc, argv);
    if (!std::strcmp(argv[1], "bench")) return ml::runBench(argc, argv);
    if (!std::strcmp(argv[1], "bake")) return ml::runBake(argc, argv);
    if (!std::strcmp(argv[1], "inspect")) return ml::runInspect(argc, argv);
    if (!std::strcmp(argv[1], "verify")) return ml::runVerify(argc, argv);
    if (!std::strcmp(argv[1], "check")) return ml::runCheck(argc, argv);
    if (!std::strcmp(argv[1], "merge")) return ml::runMerge(argc, argv);
    std::fprintf(stderr, "manylights: unknown command '%s' (see manylights help)\n", argv[1]);
    return ml::kExitUsage;
}
