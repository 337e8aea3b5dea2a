#include "report.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "visfield/field/object_field.hpp"

namespace vf::bench {

std::string with_separators(std::size_t value) {
  const std::string digits = std::to_string(value);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string padded_left(const std::string& text, std::size_t width) {
  return text.size() >= width ? text : std::string(width - text.size(), ' ') + text;
}

std::string padded_right(const std::string& text, std::size_t width) {
  return text.size() >= width ? text : text + std::string(width - text.size(), ' ');
}

namespace {

// " (4 per hit, length 2.5)" for AO rays, nothing for the other kinds.
std::string ao_details(const BenchReport& report) {
  if (report.kind != RayKind::ao) return "";
  const std::string length =
      std::isinf(report.max_distance) ? "unlimited length" : formatted("length %g", report.max_distance);
  return " (" + std::to_string(report.ao_rays) + " per hit, " + length + ")";
}

// The value, or JSON null when absent.
template <class T>
nlohmann::ordered_json or_null(const std::optional<T>& value) {
  return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json(nullptr);
}

// An exact row's mismatch count; an approximate row's differing fraction (and distance error).
std::string mismatch_cell(const ResultRow& row) {
  if (!row.approximate) return with_separators(row.mismatches);
  std::string cell = formatted("approx: %.2f%% differ", 100.0 * row.approximate->differing_fraction);
  if (row.approximate->mean_distance_error) cell += formatted(", mean |dt| %.4g", *row.approximate->mean_distance_error);
  return cell;
}

}  // namespace

double mrays_per_second(std::size_t rays, double ms) {
  return ms > 0.0 ? static_cast<double>(rays) / (ms * 1e-3) * 1e-6 : 0.0;
}

void print_table(std::ostream& out, const BenchReport& report) {
  out << "scene " << report.scene << " | " << with_separators(report.triangles) << " triangles | "
      << ray_kind_name(report.kind) << " rays: " << with_separators(report.rays) << ao_details(report) << " | threads "
      << report.threads << " | kernels " << report.isa << " | median of " << report.reps << " runs after " << report.warmup << " warm-up | "
      << (report.embree ? *report.embree : std::string("Embree not run"));
  // A timing-bound build's fields answer wrongly on purpose: its tables say so.
  if (*field::ObjectField::timing_bound() != '\0')
    out << " | TIMING BOUND: field query built " << field::ObjectField::timing_bound() << " (answers wrong)";
  out << "\n";

  std::size_t name_width = 5;
  for (const ResultRow& row : report.rows) name_width = std::max(name_width, row.accel.size());
  const std::string mismatch_title = "mismatches vs " + report.reference;
  // With more than one Embree row, a column against the fastest of them ("Embree best").
  std::size_t embree_rows = 0;
  for (const ResultRow& row : report.rows) embree_rows += row.embree ? 1 : 0;
  const bool best_column = embree_rows > 1;
  out << padded_right("accel", name_width) << "  " << padded_left("build ms", 10) << "  " << padded_left("bytes", 15)
      << "  " << padded_left("Mrays/s", 9) << "  " << padded_left("ratio to Embree", 15) << "  "
      << (best_column ? padded_left("to Embree best", 14) + "  " : std::string()) << mismatch_title << "\n";
  for (const ResultRow& row : report.rows) {
    const std::string ratio = row.ratio_to_embree ? formatted("%.2fx", *row.ratio_to_embree) : std::string("-");
    const std::string to_best = row.ratio_to_embree_best ? formatted("%.2fx", *row.ratio_to_embree_best) : std::string("-");
    out << padded_right(row.accel, name_width) << "  " << padded_left(formatted("%.1f", row.build_ms), 10) << "  "
        << padded_left(with_separators(row.bytes), 15) << "  " << padded_left(formatted("%.2f", row.mrays_per_s), 9)
        << "  " << padded_left(ratio, 15) << "  " << (best_column ? padded_left(to_best, 14) + "  " : std::string())
        << padded_left(mismatch_cell(row), mismatch_title.size()) << "\n";
  }
  if (report.embree_best && embree_rows > 1) out << "Embree best for " << ray_kind_name(report.kind) << " rays: " << *report.embree_best << "\n";
  for (const ResultRow& row : report.rows) {
    if (!row.beam_work) continue;
    const BeamWork& w = *row.beam_work;
    out << row.accel << " work per ray: " << formatted("%.1f%%", 100.0 * w.single_tile_fraction)
        << " single-tile, " << formatted("%.2f", w.tiles) << " tiles, " << formatted("%.2f", w.leaves) << " leaves, "
        << formatted("%.2f", w.triangle_tests) << " triangle tests\n";
  }
  for (const ResultRow& row : report.rows) {
    if (!row.bvh_work) continue;
    const BvhWork& w = *row.bvh_work;
    out << row.accel << " work per ray: " << formatted("%.2f", w.nodes) << " nodes, " << formatted("%.2f", w.leaves)
        << " leaves, " << formatted("%.2f", w.blocks) << " blocks, " << formatted("%.2f", w.triangle_tests) << " triangle tests\n";
  }
}

nlohmann::ordered_json report_json(const BenchReport& report) {
  nlohmann::ordered_json doc;
  doc["scene"] = report.scene;
  doc["triangles"] = report.triangles;
  doc["rays"] = report.rays;
  doc["kind"] = std::string(ray_kind_name(report.kind));
  doc["threads"] = report.threads;
  doc["isa"] = report.isa;
  doc["width"] = report.width;
  doc["height"] = report.height;
  if (report.kind == RayKind::ao) {
    doc["ao_rays"] = report.ao_rays;
    doc["max_distance"] =
        or_null(std::isinf(report.max_distance) ? std::nullopt : std::optional<float>(report.max_distance));
  }
  doc["reps"] = report.reps;
  doc["warmup"] = report.warmup;
  doc["reference"] = report.reference;
  doc["embree"] = or_null(report.embree);
  doc["embree_best"] = or_null(report.embree_best);
  nlohmann::ordered_json& results = doc["results"] = nlohmann::ordered_json::array();
  for (const ResultRow& row : report.rows) {
    results.push_back({{"accel", row.accel},
                       {"build_ms", row.build_ms},
                       {"bytes", row.bytes},
                       {"median_ms", row.median_ms},
                       {"mrays_per_s", row.mrays_per_s},
                       {"ratio_to_embree", or_null(row.ratio_to_embree)},
                       {"ratio_to_embree_best", or_null(row.ratio_to_embree_best)},
                       {"mismatches", row.mismatches}});
    if (row.approximate) {
      results.back()["mismatches"] = nullptr;
      results.back()["differing_fraction"] = row.approximate->differing_fraction;
      results.back()["mean_distance_error"] = or_null(row.approximate->mean_distance_error);
    }
    if (row.beam_work) {
      results.back()["beam_work"] = {{"single_tile_fraction", row.beam_work->single_tile_fraction},
                                     {"tiles", row.beam_work->tiles},
                                     {"leaves", row.beam_work->leaves},
                                     {"triangle_tests", row.beam_work->triangle_tests}};
    }
    if (row.bvh_work) {
      results.back()["bvh_work"] = {{"nodes", row.bvh_work->nodes},
                                    {"leaves", row.bvh_work->leaves},
                                    {"blocks", row.bvh_work->blocks},
                                    {"triangle_tests", row.bvh_work->triangle_tests}};
    }
  }
  return doc;
}

}  // namespace vf::bench
