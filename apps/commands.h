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
int runBenchCpvs(int argc, char** argv);  // apps/bench_cpvs.cpp
int runBenchSizes(int argc, char** argv); // apps/bench_sizes.cpp
int runBenchCpu(int argc, char** argv);   // apps/bench_cpu.cpp
int runMerge(int argc, char** argv);
int usageError(const char* command, const std::string& message); // exit code 2
int runError(const char* command, const std::string& message);   // exit code 1
// The start every command shares: its parsed flags, or none with `status` set to the exit status
// (0 after printing `help` for --help, 2 after printing the parse error).
std::optional<cli::Args> commandArgs(const char* command, const char* help, Result<cli::Args> args,
                                     int& status);
} // namespace ml
