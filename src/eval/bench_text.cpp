// The printed report of `freespace bench`: see bench_report.hpp. Field definitions:
// docs/bench.md.
#include <cmath>

#include "eval/bench_report.hpp"

namespace freespace {
namespace {

constexpr const char* kStages[] = {"preprocess", "align",   "rasterize", "fuse",
                                   "classify",   "insight", "polygon",   "total"};

double Ratio(double a, double b) { return b > 0 ? a / b : NAN; }
// Non-finite values print as nan, as they are null in bench.json.
double Finite(double v) { return std::isfinite(v) ? v : NAN; }

void Line(std::FILE* out, const char* label, double a, double b, const char* unit,
          const char* note = "") {
  std::fprintf(out, "  %-36s %12.1f %12.1f %s %s\n", label, a, b, unit, note);
}
void Line4(std::FILE* out, const char* label, double a, double b) {
  std::fprintf(out, "  %-36s %12.4f %12.4f\n", label, a, b);
}

void PrintPipelines(std::FILE* out, const BenchReport& report) {
  std::fprintf(out, "Pipeline, median / p99 microseconds per scan\n");
  const std::vector<const BackendPipeline*> ran = report.Ran();
  for (const BackendPipeline* pipeline : ran) {
    const PipelineRun& r = pipeline->run;
    std::string wait;
    if (r.opencl_wait == "auto") {
      wait = ", wait auto (spins at most " + std::to_string(r.opencl_spin_us) + " us)";
    } else if (!r.opencl_wait.empty()) {
      wait = ", wait " + r.opencl_wait;
    }
    std::fprintf(out, "  %s%s (%.0f scans/s)\n", r.backend.c_str(), wait.c_str(),
                 1e6 / r.times.Mean("total"));
    for (const char* stage : kStages) {
      Line(out, stage, r.times.Quantile(stage, 0.5), r.times.Quantile(stage, 0.99), "us");
    }
  }
  if (ran.size() == 2) {
    std::fprintf(out, "  opencl / tbb median, per stage:");
    for (const char* stage : kStages) {
      std::fprintf(
          out, " %s %.2f", stage,
          Ratio(ran[1]->run.times.Quantile(stage, 0.5), ran[0]->run.times.Quantile(stage, 0.5)));
    }
    std::fprintf(out, "\n");
  }
}

void PrintQuality(std::FILE* out, const TruthQuality& e, const TruthQuality& c) {
  std::fprintf(out, "  against the truth (docs/metrics.md), %ld scans scored:\n", e.scans);
  Line4(out, "accuracy on observed cells (pooled)", e.accuracy, c.accuracy);
  Line4(out, "accuracy, mean of scans", e.accuracy_mean, c.accuracy_mean);
  Line(out, "observed cells", e.observed_cells, c.observed_cells, "cells/scan");
  Line4(out, "false-free rate (pooled)", e.false_free_rate, c.false_free_rate);
  Line(out, "false-occupied cells", e.false_occupied, c.false_occupied, "cells/scan");
  Line4(out, "polygon coverage (pooled)", e.coverage, c.coverage);
}

void PrintSensorModels(std::FILE* out, const BenchReport& report) {
  const PipelineRun &e = report.enhanced, &c = report.conventional;
  const BenchComparisons& paper = report.comparisons;
  std::fprintf(out, "\nInverse sensor model (paper II, V.B)         enhanced conventional\n");
  Line(out, "model (rasterize + fuse), median", ModelUs(e), ModelUs(c), "us");
  Line(out, "map building (preprocess .. fuse)", MapUs(e), MapUs(c), "us");
  Line(out, "full pipeline, median", TotalUs(e), TotalUs(c), "us");
  std::fprintf(
      out, "  conventional / enhanced: model %.2f, map building %.2f, full pipeline %.2f\n",
      paper.enhanced_model_speedup, paper.enhanced_map_speedup, paper.enhanced_total_speedup);
  const CoverageStats& coverage = report.coverage;
  const FootprintStats &fe = coverage.enhanced, &fc = coverage.conventional;
  std::fprintf(out, "  footprint: %.0f cells a scan, %d scans measured\n", coverage.footprint_cells,
               coverage.scans);
  Line(out, "footprint cells without update", fe.holes, fc.holes, "cells/scan");
  Line(out, "  of which Moire (between updates)", fe.moire, fc.moire, "cells/scan");
  Line(out, "conflicts (free and occupied)", fe.conflicts, fc.conflicts, "cells/scan");
  Line(out, "  of which echo erased (net free)", fe.conflicts_free, fc.conflicts_free,
       "cells/scan");
  Line(out, "updates per updated footprint cell", fe.mean_updates, fc.mean_updates, "");
  Line(out, "most updates in one cell", fe.max_updates, fc.max_updates, "");
  if (report.enhanced_quality && report.conventional_quality) {
    PrintQuality(out, *report.enhanced_quality, *report.conventional_quality);
  }
}

void PrintAlignment(std::FILE* out, const AlignmentComparison& a) {
  std::fprintf(out, "\nMap alignment (paper III, V.B)                 circle       rotate\n");
  Line(out, "align, median", a.circle.times.Quantile("align", 0.5),
       a.rotate.times.Quantile("align", 0.5), "us");
  Line(out, "map building (preprocess .. fuse)", MapUs(a.circle), MapUs(a.rotate), "us");
  Line(out, "full pipeline, median", TotalUs(a.circle), TotalUs(a.rotate), "us");
  Line4(out, "cells differing from reference", a.circle_error.different_fraction,
        a.rotate_error.different_fraction);
  Line4(out, "free/unknown/occupied mismatch", a.circle_error.class_mismatch,
        a.rotate_error.class_mismatch);
  Line4(out, "mean |p - p_reference|", a.circle_error.mean_abs_probability,
        a.rotate_error.mean_abs_probability);
}

void PrintPolygonShapes(std::FILE* out, const BenchReport& r) {
  std::fprintf(out,
               "\nPolygon (median us per scan, TBB)              paper       inside   ratio\n");
  for (const char* stage : {"preprocess", "align", "rasterize", "fuse", "classify", "mask",
                            "insight", "polygon", "total"}) {
    const double a = r.paper_shape.times.Quantile(stage, 0.5);
    const double b = r.inside_shape.times.Quantile(stage, 0.5);
    if (a > 0) {
      std::fprintf(out, "  %-36s %10.1f   %10.1f   %5.2f\n", stage, a, b, b / a);
    } else {  // the paper's polygon has no mask stage: no ratio
      std::fprintf(out, "  %-36s %10.1f   %10.1f       -\n", stage, a, b);
    }
  }
}

void PrintMapScaling(std::FILE* out, const BenchReport& report, const ScalingResults& s) {
  std::fprintf(out, "\nMap size, median full pipeline microseconds per scan\n  %-10s", "cells");
  for (const BackendPipeline* pipeline : report.Ran()) {
    std::fprintf(out, " %12s", ToString(pipeline->kind));
  }
  std::fprintf(out, "\n");
  for (const int cells : kMapSizes) {
    std::fprintf(out, "  %4d^2    ", cells);
    for (const ScalePoint& p : s.map) {
      if (p.x == double(cells) * cells) std::fprintf(out, " %12.1f", p.total_us);
    }
    std::fprintf(out, "\n");
  }
  std::fprintf(out, "  exponent of time against cells (all sizes / from 600^2):");
  for (const auto& [name, e] : s.map_exponent) {
    std::fprintf(out, " %s %.2f / %.2f", name.c_str(), Finite(e.all), Finite(e.upper));
  }
}

void PrintPointsScaling(std::FILE* out, const ScalingResults& s) {
  std::fprintf(out,
               "\n\nPoints per scan (%s, 4 layers, resolution varied), median microseconds:"
               "\n  full pipeline (in brackets: rasterize + fuse)\n  %-8s",
               s.points_scenario.c_str(), "points");
  const std::vector<ScaleSeries> series = GroupScalePoints(s.points, true);
  for (const ScaleSeries& line : series) std::fprintf(out, " %24s", line.name.c_str());
  std::fprintf(out, "\n");
  for (std::size_t i = 0; i < s.points.size(); i += series.size()) {
    std::fprintf(out, "  %-8.0f", s.points[i].x);
    for (std::size_t k = i; k < i + series.size() && k < s.points.size(); ++k) {
      char cell[40];
      std::snprintf(cell, sizeof cell, "%.1f (%.1f)", s.points[k].total_us, s.points[k].model_us);
      std::fprintf(out, " %24s", cell);
    }
    std::fprintf(out, "\n");
  }
}

// What a map-size exponent says about the growth of time with the cells.
const char* Growth(double upper) {
  return upper <= 1.0               ? "no faster than linearly"
         : upper <= kLinearExponent ? "about linearly (within the run-to-run noise)"
                                    : "FASTER than linearly";
}

void PrintComparisons(std::FILE* out, const BenchReport& report) {
  const BenchComparisons& c = report.comparisons;
  std::fprintf(out, "\nThe paper's comparisons, this run\n");
  std::fprintf(out,
               "  enhanced vs conventional: model %.2fx faster; %.1f %% less time building the "
               "map, %.1f %% less for the full pipeline (paper: %.2f %s less)\n",
               c.enhanced_model_speedup, c.enhanced_map_time_saved_percent,
               c.enhanced_time_saved_percent, kPaperFigures.enhanced_time_saved.value,
               kPaperFigures.enhanced_time_saved.unit);
  if (report.enhanced_quality && report.conventional_quality) {
    std::fprintf(out, "  accuracy on observed cells: enhanced %.4f, conventional %.4f\n",
                 report.enhanced_quality->accuracy, report.conventional_quality->accuracy);
  }
  std::fprintf(out,
               "  circle vs rotate: %.1f %% less time building the map, %.1f %% less for the "
               "full pipeline (paper: %.2f %s); cells differing from the reference: circle "
               "%.4f, rotate %.4f\n",
               c.circle_map_time_saved_percent, c.circle_time_saved_percent,
               kPaperFigures.circle_time_saved.value, kPaperFigures.circle_time_saved.unit,
               c.circle_different_fraction, c.rotate_different_fraction);
  const std::vector<const BackendPipeline*> ran = report.Ran();
  if (!ran.empty()) {
    std::fprintf(out, "  full pipeline median on %s: %.1f us (map %d x %d, %.0f points a scan)\n",
                 ran[0]->run.backend.c_str(), TotalUs(ran[0]->run), report.map_width,
                 report.map_height, report.points_per_scan);
  }
  if (c.opencl_over_tbb_total) {
    std::fprintf(out, "  opencl / tbb full pipeline: %.2f\n", *c.opencl_over_tbb_total);
  }
  if (report.scaling) {
    for (const auto& [name, e] : report.scaling->map_exponent) {
      const double upper = Finite(e.upper);
      std::fprintf(out, "  %s: time grows as cells^%.2f from 600^2 to 3000^2: %s\n", name.c_str(),
                   upper, Growth(upper));
    }
  }
  std::fprintf(out, "  load average %.2f at the start, %.2f at the end (a shared machine)\n",
               report.load_before, report.load_after);
}

}  // namespace

void PrintBenchReport(std::FILE* out, const BenchReport& report) {
  std::fprintf(out,
               "freespace bench: %s, %zu scans (%d warm-up), %.0f points a scan, map %d x %d at "
               "%.2f m\n\n",
               report.source.Describe().c_str(), report.scans, report.warmup,
               report.points_per_scan, report.map_width, report.map_height, report.resolution_m);
  PrintPipelines(out, report);
  PrintSensorModels(out, report);
  PrintAlignment(out, report.alignment);
  PrintPolygonShapes(out, report);
  if (report.scaling) {
    PrintMapScaling(out, report, *report.scaling);
    PrintPointsScaling(out, *report.scaling);
  }
  PrintComparisons(out, report);
}

}  // namespace freespace
