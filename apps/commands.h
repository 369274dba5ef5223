// Subcommands of the `manylights` command line. Each prints --help and exits non-zero with one line
// naming the problem on bad input.
#pragma once
#include "apps/cli.h"

#include <optional>
#include <string>

namespace ml {
int runDemo(int argc, char** argv);
int runBench(int argc, char** argv);
int runBenchStatic(int argc, char** argv);
int runBenchStaticNeed(int argc, char** argv); // bench static --need (apps/bench_static_need.cpp)
int runBenchFlicker(int argc, char** argv);
int runBake(int argc, char** argv);
int runInspect(int argc, char** argv);
int runVerify(int argc, char** argv);
int runCheck(int argc, char** argv);
int runBenchVsm(int argc, char** argv);
// bench vsm-rays: apps/bench_vsm_rays.cpp
int runBenchVsmRays(int argc, char** argv);
int runBenchCpvs(int argc, char** argv);   // apps/bench_cpvs.cpp
int runBenchSizes(int argc, char** argv);  // apps/bench_sizes.cpp
int runBenchCpu(int argc, char** argv);    // apps/bench_cpu.cpp
int runBenchRecord(int argc, char** argv); // apps/bench_record.cpp
int runBenchSoak(int argc, char** argv);   // apps/bench_soak.cpp
int runMerge(int argc, char** argv);
// Exit statuses of every command (README "Exit status"; `manylights help`).
constexpr int kExitUsage = 1; // the command line: bad, missing, repeated or useless options, ranges, limits
constexpr int kExitInput = 2; // a hostile or malformed input file: scene, bake file, part
constexpr int kExitRun = 3;   // the run failed: device, output, validation messages, mismatches found
// One escaped line "manylights COMMAND: MESSAGE" on stderr; each returns its exit status.
int usageError(const char* command, const std::string& message); // kExitUsage
int inputError(const char* command, const std::string& message); // kExitInput
int runError(const char* command, const std::string& message);   // kExitRun
// The start every command shares: its parsed flags, or none with `status` set to the exit status
// (0 after printing `help` for --help, kExitUsage after printing the parse error).
std::optional<cli::Args> commandArgs(const char* command, const char* help, Result<cli::Args> args,
                                     int& status);
} // namespace ml
