#include "apps/bench_static_tables.h"

#include "io/safe_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace ml {

// The main table on stdout; returns bench_static.csv's text.
std::string printMainTable(const std::vector<BenchStaticRow>& rows) {
    std::printf("| method | res | bytes/light | vs 32-bit map | render s | encode s | eval ms | eval vs sm | "
                "wrong %% |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    std::ostringstream csv;
    csv << "method,res,lights,bytes_total,map32_bytes,render_s,encode_s,eval_ms,eval_vs_sm,compared,"
           "disagreement,"
           "mean_abs_diff,cpvs_precompute_s,cpvs_insert_s,cpvs_compress_s\n";
    for (const BenchStaticRow& r : rows) {
        if (!r.failed.empty()) {
            std::printf("| %s | %u | %s |\n", r.method.c_str(), r.res, r.failed.c_str());
            csv << r.method << "," << r.res << "," << r.lights << ",,,,,,,,,,,,\n";
            continue;
        }
        double smMs = -1;
        for (const BenchStaticRow& s : rows)
            if (s.method == "sm" && s.res == r.res) smMs = s.evalMs;
        const bool measured = r.evalMs >= 0;
        double vsSm = smMs > 0 && measured ? r.evalMs / smMs : 0;
        double rate = r.compared ? double(r.mismatches) / r.compared : 0;
        char eval[32] = "-", ratio[32] = "-", wrong[32] = "-";
        if (measured) {
            std::snprintf(eval, sizeof(eval), "%.1f", r.evalMs);
            std::snprintf(wrong, sizeof(wrong), "%.3f", 100.0 * rate);
        }
        if (vsSm > 0) std::snprintf(ratio, sizeof(ratio), "%.2fx", vsSm);
        std::printf("| %s | %u | %.0f | 1/%.1f | %.2f | %.2f | %s | %s | %s |\n", r.method.c_str(), r.res,
                    double(r.bytes) / r.lights, double(r.mapBytes) / r.bytes, r.renderS, r.encodeS, eval,
                    ratio, wrong);
        csv << r.method << "," << r.res << "," << r.lights << "," << r.bytes << "," << r.mapBytes << ","
            << r.renderS << "," << r.encodeS << "," << r.evalMs << "," << vsSm << "," << r.compared << ","
            << rate << "," << r.meanAbs << "," << r.precomputeS << "," << r.insertS << "," << r.compressS
            << "\n";
    }
    return csv.str();
}

void printCpvsSplit(const std::vector<BenchStaticRow>& rows) {
    bool anyCpvs = false;
    for (const BenchStaticRow& r : rows) anyCpvs |= r.method == "cpvs";
    if (anyCpvs) {
        std::printf("\nCPVS bake split (paper Table 3), seconds over all lights; bytes per light against a "
                    "16-bit map:\n");
        std::printf("| res | render maps | precompute | insert | compress | insert+compress vs render | "
                    "bytes/light | vs 16-bit map |\n");
        std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for (const BenchStaticRow& r : rows)
            if (r.method == "cpvs")
                std::printf("| %u | %.3f | %.3f | %.3f | %.3f | %.2fx | %.0f | 1/%.0f |\n", r.res, r.renderS,
                            r.precomputeS, r.insertS, r.compressS, (r.insertS + r.compressS) / r.renderS,
                            double(r.bytes) / r.lights,
                            double(r.res) * r.res * 2.0 / (double(r.bytes) / r.lights));
    }
}

// One data file per method (gnuplot joins the points of a file with lines), then two charts.
Result<void> writeCharts(const std::string& dir, const std::vector<BenchStaticRow>& rows) {
    std::vector<std::string> methods;
    for (const BenchStaticRow& r : rows)
        if (std::find(methods.begin(), methods.end(), r.method) == methods.end()) methods.push_back(r.method);
    std::string script = dir + "/charts.gp";
    std::ostringstream gp;
    gp << "set terminal pngcairo size 900,600\nset key outside right\nset grid\nset logscale x 2\n"
          "set ylabel 'disagreement with ray-traced visibility (%)'\n";
    for (const auto& m : methods) {
        std::ostringstream dat;
        dat << "# bytes_per_light eval_ms disagreement_percent res one_tap_lookup_ns\n";
        for (const BenchStaticRow& r : rows)
            if (r.method == m && r.evalMs >= 0 && r.failed.empty()) {
                // The isolated one-tap lookup cost, or NaN (gnuplot skips it) when not measured.
                double ns = std::nan("");
                for (const LookupTiming& t : r.lookup)
                    if (t.radius == 0) ns = t.nsPerLookup;
                dat << double(r.bytes) / r.lights << " " << r.evalMs << " "
                    << (r.compared ? 100.0 * double(r.mismatches) / r.compared : 0.0) << " " << r.res << " "
                    << ns << "\n";
            }
        if (auto w = io::writeFileAtomically(dir + "/" + m + ".dat", dat.str()); !w) return w;
    }
    const bool anyLookup = std::any_of(rows.begin(), rows.end(), [](const BenchStaticRow& r) {
        return std::any_of(r.lookup.begin(), r.lookup.end(),
                           [](const LookupTiming& t) { return t.radius == 0; });
    });
    for (int chart = 0; chart < (anyLookup ? 3 : 2); ++chart) {
        const char* names[3] = {"/accuracy_vs_bytes.png'\n", "/accuracy_vs_time.png'\n",
                                "/accuracy_vs_lookup.png'\n"};
        const char* xlabels[3] = {
            // Binary prefixes on the power-of-two ticks (64 KiB ... 8 MiB), not 1.04858x10^6.
            "set format x '%.0b %BB'\nset xlabel 'bytes per light'\n",
            "set format x '%g'\nunset logscale x\nset xlabel 'evaluation pass, GPU ms (same lights, same "
            "view)'\n",
            "set format x '%g'\nset xlabel 'one-tap lookup, ns (isolated pass)'\n"};
        const int column[3] = {1, 2, 5};
        gp << "set output '" << dir << names[chart] << xlabels[chart] << "plot ";
        for (size_t i = 0; i < methods.size(); ++i)
            gp << (i ? ", " : "") << "'" << dir << "/" << methods[i] << ".dat' using " << column[chart]
               << ":3 with linespoints title '" << methods[i] << "'";
        gp << "\n";
    }
    if (auto w = io::writeFileAtomically(script, gp.str()); !w) return w;
    std::string cmd = "gnuplot '" + script + "' 2>&1";
    if (std::system(cmd.c_str()) != 0)
        return fail("gnuplot failed on " + script + " (is gnuplot-nox installed?)");
    return {};
}

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

void printBoundsTable(const std::vector<BenchStaticRow>& rows) {
    bool header = false;
    for (const BenchStaticRow& r : rows) {
        const uint64_t one = r.boundsOneTap[0] + r.boundsOneTap[1] + r.boundsOneTap[2];
        const uint64_t pcf = r.bounds3x3[0] + r.bounds3x3[1] + r.bounds3x3[2];
        if (r.method != "dagmh" || one == 0 || pcf == 0) continue;
        if (!header)
            std::printf(
                "DAG-MH value bounds: share of in-map lookups answered from one word (lit + shadowed)\n"
                "  res     one tap: lit  shadowed  undecided     3x3 PCF: lit  shadowed  undecided\n");
        header = true;
        auto pct = [](uint64_t a, uint64_t n) { return 100.0 * double(a) / double(n); };
        std::printf("  %5u   %12.1f%% %8.1f%% %9.1f%%  %12.1f%% %8.1f%% %9.1f%%\n", r.res,
                    pct(r.boundsOneTap[1], one), pct(r.boundsOneTap[2], one), pct(r.boundsOneTap[0], one),
                    pct(r.bounds3x3[1], pcf), pct(r.bounds3x3[2], pcf), pct(r.bounds3x3[0], pcf));
    }
}

} // namespace ml
