// `bench static`'s per-configuration results and the tables printed from them beside the main one:
// disagreements by cause with their convergence slopes (bench_classes.csv) and the isolated lookup
// cost (bench_lookup.csv).
#pragma once
#include "shadows/tools/lookup_timer.h"
#include "manylights/result.h"
#include "bake/reference/error_classes.h"
#include "shadows/static/static_method.h"

#include <string>
#include <vector>

namespace ml {

// One method at one resolution.
struct BenchStaticRow {
    std::string method;
    uint32_t res = 0, lights = 0;
    uint64_t bytes = 0, mapBytes = 0;
    double renderS = 0, encodeS = 0, evalMs = 0;
    double precomputeS = 0, insertS = 0, compressS = 0; // CPVS: the paper's Table 3 split of encodeS
    std::string failed;                                 // the encoder's error when it cannot encode a map
    uint64_t compared = 0, mismatches = 0;
    double meanAbs = 0;
    std::vector<LookupTiming> lookup; // per --lookup-pcf radius; empty when not measured
    std::string lookupSkipped;        // why not (e.g. past the device's storage buffer range)
    ErrorCounts classes{};            // disagreements by cause (bake/reference/error_classes.h)
    // DAG-MH: how the compared receivers' lookups are answered (dagmhBoundsDecision: [0] undecided,
    // [1] lit and [2] shadowed by the value bounds alone, [3] off the map or before its near plane), for the
    // one tap and 3x3 PCF.
    uint64_t boundsOneTap[4]{}, bounds3x3[4]{};
};

// DAG-MH rows: the share of lookups the value bounds answer from one word (one tap and 3x3 PCF).
void printBoundsTable(const std::vector<BenchStaticRow>& rows);
// The main table (bytes, bake split, evaluation time, wrong %) on stdout; returns bench_static.csv's text.
std::string printMainTable(const std::vector<BenchStaticRow>& rows);
// CPVS's bake split (the paper's Table 3), when a CPVS row ran.
void printCpvsSplit(const std::vector<BenchStaticRow>& rows);
// Per method a data file and, with gnuplot, the charts of accuracy against bytes, time and lookup cost.
Result<void> writeCharts(const std::string& dir, const std::vector<BenchStaticRow>& rows);

// Prints the cause breakdown (shares of compared receivers) and, per method, the least-squares slope
// of log(rate) on log(res) for the resolution class, all disagreements and contact; writes
// <dir>/bench_classes.csv (counts).
Result<void> printClassTables(const std::string& dir, const std::vector<BenchStaticRow>& rows,
                              const std::vector<StaticMethod>& methods);

// Prints ns per lookup per PCF size; writes <dir>/bench_lookup.csv.
Result<void> printLookupTable(const std::string& dir, const std::vector<BenchStaticRow>& rows,
                              const std::vector<uint32_t>& lookupRadii, size_t pairs, uint32_t extraLookups);

} // namespace ml
