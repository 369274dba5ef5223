#include "apps/bench_static_tables.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace ml {

Result<void> printClassTables(const std::string& dir, const std::vector<BenchStaticRow>& rows,
                              const std::vector<StaticMethod>& methods) {
    using Row = BenchStaticRow;
    // Disagreements by cause, as shares of the compared receivers (they add up to "wrong %"), and the
    // convergence of the resolution class: the least-squares slope of log(rate) against log(res).
    std::printf("\nDisagreement by cause, %% of compared receivers (bake/reference/error_classes.h):\n");
    std::printf("| method | res | wrong %% |");
    for (uint32_t c = 0; c < kErrorClassCount; ++c) std::printf(" %s %% |", errorClassName(ErrorClass(c)));
    std::printf("\n|---|---:|---:|");
    for (uint32_t c = 0; c < kErrorClassCount; ++c) std::printf("---:|");
    std::printf("\n");
    std::ostringstream ccsv;
    ccsv << "method,res,compared,mismatches";
    for (uint32_t c = 0; c < kErrorClassCount; ++c) ccsv << "," << errorClassName(ErrorClass(c));
    ccsv << "\n";
    for (const Row& r : rows) {
        if (!r.compared) continue;
        std::printf("| %s | %u | %.3f |", r.method.c_str(), r.res, 100.0 * double(r.mismatches) / r.compared);
        ccsv << r.method << "," << r.res << "," << r.compared << "," << r.mismatches;
        for (uint32_t c = 0; c < kErrorClassCount; ++c) {
            std::printf(" %.3f |", 100.0 * double(r.classes[c]) / r.compared);
            ccsv << "," << r.classes[c];
        }
        std::printf("\n");
        ccsv << "\n";
    }
    std::printf(
        "\nConvergence with resolution: least-squares slope of log(class rate) on log(res) "
        "(-1 = halves per doubling; 0 = a floor):\n| method | resolution class | all "
        "disagreements | contact | resolution %% at lowest -> highest res |\n|---|---:|---:|---:|---|\n");
    for (StaticMethod method : methods) {
        auto slope = [&](auto value) {
            double sx = 0, sy = 0, sxx = 0, sxy = 0;
            int n = 0;
            for (const Row& r : rows)
                if (r.method == staticMethodName(method) && r.compared && value(r) > 0) {
                    double x = std::log2(double(r.res)), y = std::log2(value(r));
                    sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
                }
            return n >= 2 && sxx * n - sx * sx > 0 ? (n * sxy - sx * sy) / (n * sxx - sx * sx) : std::nan("");
        };
        auto rate = [](const Row& r, uint64_t k) { return double(k) / double(r.compared); };
        double sRes =
            slope([&](const Row& r) { return rate(r, r.classes[uint32_t(ErrorClass::Resolution)]); });
        double sAll = slope([&](const Row& r) { return rate(r, r.mismatches); });
        double sCon = slope([&](const Row& r) { return rate(r, r.classes[uint32_t(ErrorClass::Contact)]); });
        std::string path;
        for (const Row& r : rows)
            if (r.method == staticMethodName(method) && r.compared) {
                char b[32];
                std::snprintf(b, sizeof(b), "%s%.3f", path.empty() ? "" : " -> ",
                              100.0 * rate(r, r.classes[uint32_t(ErrorClass::Resolution)]));
                path += b;
            }
        std::printf("| %s | %.2f | %.2f | %.2f | %s |\n", staticMethodName(method), sRes, sAll, sCon,
                    path.c_str());
    }
    {
        std::ofstream cf(dir + "/bench_classes.csv");
        if (!cf || !(cf << ccsv.str())) return fail(dir + "/bench_classes.csv: cannot write");
    }

    return {};
}

Result<void> printLookupTable(const std::string& dir, const std::vector<BenchStaticRow>& rows,
                              const std::vector<uint32_t>& lookupRadii, size_t pairs, uint32_t extraLookups) {
    using Row = BenchStaticRow;
    std::printf(
        "\nIsolated lookup cost, ns per lookup (%zu pairs, timed at 1 and 1 + K lookups each, K >= %u "
        "grown until the K lookups take >= 40 ms; min of 3; spread = (max - min) / min):\n",
        pairs, extraLookups);
    std::printf("| method | res |");
    for (uint32_t r : lookupRadii) std::printf(" %ux%u ns |", 2 * r + 1, 2 * r + 1);
    std::printf(" max spread | GPU != CPU |\n|---|---:|");
    for (size_t i = 0; i < lookupRadii.size(); ++i) std::printf("---:|");
    std::printf("---:|---:|\n");
    std::ostringstream lcsv;
    lcsv << "method,res,pcf_radius,taps,ns_per_lookup,spread,gpu_cpu_mismatches,pairs,extra_lookups\n";
    for (const Row& r : rows) {
        if (r.lookup.empty()) {
            std::printf("| %s | %u | %s |\n", r.method.c_str(), r.res,
                        r.lookupSkipped.empty() ? (r.failed.empty() ? "not measured" : "cannot encode")
                                                : r.lookupSkipped.c_str());
            continue;
        }
        double spread = 0;
        uint64_t mism = 0;
        std::printf("| %s | %u |", r.method.c_str(), r.res);
        for (const LookupTiming& t : r.lookup) {
            std::printf(" %.1f |", t.nsPerLookup);
            spread = std::max(spread, t.spread);
            mism += t.cpuMismatches;
            lcsv << r.method << "," << r.res << "," << t.radius << ","
                 << (2 * t.radius + 1) * (2 * t.radius + 1) << "," << t.nsPerLookup << "," << t.spread << ","
                 << t.cpuMismatches << "," << pairs << "," << t.lookups << "\n";
        }
        std::printf(" %.0f%% | %llu |\n", 100.0 * spread, (unsigned long long)mism);
    }
    std::ofstream lf(dir + "/bench_lookup.csv");
    if (!lf || !(lf << lcsv.str())) return fail(dir + "/bench_lookup.csv: cannot write");
    return {};
}

} // namespace ml
