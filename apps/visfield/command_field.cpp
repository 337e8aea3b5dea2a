#include <filesystem>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <iostream>
#include <memory>
#include <optional>

#include "cli_support.hpp"
#include "commands.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/text.hpp"
#include "visfield/field/field_file.hpp"
#include "visfield/field/field_params.hpp"
#include "visfield/io/atomic_file.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/select/calibration.hpp"
#include "visfield/registry/planning.hpp"
#include "visfield/render/progress.hpp"

namespace vf::cli {

namespace {

struct FieldBuildOptions {
  std::string mesh;
  std::map<std::string, std::string, std::less<>> table;  ///< field::kTableParams' values as written.
  std::string out;
  int threads = 0;
  bool no_progress = false;
  double target_rms = 0.0;   ///< > 0: positions and directions from the planner's error model.
  std::string calibration;   ///< Calibration file holding that model (empty: built in).
};

// The positions and directions of the smallest field the calibration's error model expects to keep
// the AO image's RMS within `o.target_rms` for `scene`; writes them into `table` and says so.
void size_for_target_rms(const FieldBuildOptions& o, const Scene& scene,
                         std::map<std::string, std::string, std::less<>>& table) {
  const Calibration calibration = o.calibration.empty() ? builtin_calibration() : load_calibration(o.calibration);
  const FieldErrorModel& model = calibration.plan.field_error;
  if (model.samples == 0)
    throw Error("--target-rms: " + (o.calibration.empty() ? std::string("the built-in calibration") : o.calibration) +
                " has no field error model (run visfield calibrate without --no-plan)");
  SceneGeometry geometry(scene);
  const SceneProfile profile = profile_for_plan(geometry, {}, true);
  char line[256];
  double measured_rms = -1.0;
  std::optional<FieldErrorImage> image;  // made at the first measurement, for all of them
  const std::size_t pick = field_for_target_rms(model, profile, o.target_rms, [&](std::size_t candidate) {
    if (!image) image.emplace(geometry);
    measured_rms = image->rms(build_structure(plan_candidates()[candidate].spec, geometry, {}, "--target-rms ").structure);
    std::snprintf(line, sizeof line, "measured %s: RMS %.2f (the error model can neither rule it out for %g nor vouch for it)\n",
                  std::string(plan_candidates()[candidate].spec).c_str(), measured_rms, o.target_rms);
    std::cout << line;
    return measured_rms;
  });
  if (pick >= plan_candidates().size()) {
    int finest_positions = 0, finest_directions = 0;
    double finest = std::numeric_limits<double>::infinity();
    for (const PlanCandidate& c : plan_candidates())
      if (c.approximate() && model.bound(c.positions, c.directions, profile.ao_occluded, profile.field_probe_rms) < finest)
        finest = model.bound(c.positions, c.directions, profile.ao_occluded, profile.field_probe_rms), finest_positions = c.positions,
        finest_directions = c.directions;
    std::snprintf(line, sizeof line, "--target-rms %g: no field the planner weighs is expected to meet it (lowest bound %.2f, positions=%d,directions=%d)",
                  o.target_rms, finest, finest_positions, finest_directions);
    throw Error(line);
  }
  const PlanCandidate& c = plan_candidates()[pick];
  table["positions"] = std::to_string(c.positions);
  table["directions"] = std::to_string(c.directions);
  const double bound = model.bound(c.positions, c.directions, profile.ao_occluded, profile.field_probe_rms);
  const std::string why = bound <= o.target_rms ? "expected RMS " + formatted("%.2f", model.predict(c.positions, c.directions, profile.ao_occluded,
                                                                                                  profile.field_probe_rms)) +
                                                      ", 90% bound " + formatted("%.2f", bound)
                                                : "measured RMS " + formatted("%.2f", measured_rms);
  std::snprintf(line, sizeof line, "sized for RMS <= %g: positions=%d, directions=%d (%s; probe %s RMS %.2f, AO rays occluded %.3f)\n",
                o.target_rms, c.positions, c.directions, why.c_str(), std::string(kFieldProbe).c_str(), profile.field_probe_rms,
                profile.ao_occluded);
  std::cout << line;
}

// The one mesh the argument names (a mesh file, or a scene whose objects all use one mesh).
const TriangleMesh& the_mesh(const Scene& scene, const std::string& argument) {
  const TriangleMesh* mesh = nullptr;
  for (const Instance& object : scene.instances()) {
    if (mesh && mesh != &scene.meshes[object.mesh])
      throw Error(argument + ": a field is built for one mesh; this scene's objects use several (give a mesh file)");
    mesh = &scene.meshes[object.mesh];
  }
  if (!mesh) throw Error(argument + ": no object to build a field for");
  return *mesh;
}

int run_field_build(const FieldBuildOptions& o) {
  if (std::filesystem::path(o.out).extension() != ".vfield") throw Error("-o " + o.out + ": the file name must end in .vfield");
  check_writable(o.out);
  const auto spec_of = [](const std::map<std::string, std::string, std::less<>>& table) {
    std::string spec = "field";
    for (const auto& [key, value] : table) spec += (spec == "field" ? ":" : ",") + key + "=" + value;
    return spec;
  };
  field_config_from_spec(spec_of(o.table), "");  // bad values fail before the mesh loads
  ThreadLimit limit(o.threads);
  const Scene scene = load_scene_argument(o.mesh);
  const TriangleSet triangles = mesh_triangles(the_mesh(scene, o.mesh));
  if (triangles.size() == 0) throw Error(o.mesh + ": no triangles of non-zero area");
  std::map<std::string, std::string, std::less<>> table = o.table;
  if (o.target_rms > 0.0) size_for_target_rms(o, scene, table);
  const field::ObjectFieldConfig config = field_config_from_spec(spec_of(table), "");
  ProgressBar bar("field", static_cast<std::size_t>(config.positions), !o.no_progress);
  const field::ObjectField built = field::ObjectField::build(triangles, config, [&](std::size_t n) { bar.tick(n); });
  bar.finish();
  field::save_field(built, field::mesh_hash(triangles), o.out);
  std::cout << "wrote " << std::filesystem::absolute(o.out).string() << "\n"
            << "field: " << config.positions << " positions x " << config.directions << "^2 " << field::mapping_name(config.mapping)
            << " " << field::storage_name(config.storage) << " cells"
            << (config.normals == field::NormalStorage::none ? std::string() : ", " + field::normals_name(config.normals) + " normals")
            << " of " << triangles.size() << " triangles, "
            << format_bytes(static_cast<double>(built.memory_bytes())) << ", precomputed in " << built.build_ms() / 1000.0
            << " s (" << built.rays_traced() << " rays, " << limit.threads() << " threads)\n";
  return 0;
}

int run_field_info(const std::string& path) {
  const field::StoredField stored = field::load_field(path);
  const field::ObjectField& f = stored.field;
  const field::ObjectFieldConfig& c = f.config();
  std::size_t hits = 0, cells = 0;
  for (std::size_t k = 0; k < f.position_count(); ++k)
    for (int j = 0; j < c.directions; ++j)
      for (int i = 0; i < c.directions; ++i) {
        if (!field::cell_used<double>(c.mapping, i, j, c.directions)) continue;
        ++cells;
        hits += f.cell(k, i, j).hit ? 1 : 0;
      }
  const Vec3f& centre = f.sphere().centre;
  std::cout << "file:        " << path << " (.vfield version " << stored.version << ")\n"
            << "positions:   " << c.positions << "\n"
            << "directions:  " << c.directions << " x " << c.directions << " " << field::mapping_name(c.mapping) << "\n"
            << "storage:     " << field::storage_name(c.storage) << "\n"
            << "normals:     " << field::normals_name(c.normals) << "\n"
            << "sphere:      centre (" << centre.x << ", " << centre.y << ", " << centre.z << "), radius " << f.sphere().radius << "\n"
            << "mesh hash:   " << std::hex << stored.mesh_hash << std::dec << "\n"
            << "memory:      " << format_bytes(static_cast<double>(f.memory_bytes())) << "\n"
            << "hit cells:   " << hits << " of " << cells << "\n"
            << "precompute:  " << f.build_ms() / 1000.0 << " s, " << f.rays_traced() << " rays\n";
  return 0;
}

}  // namespace

void register_field_command(CLI::App& app, Action& action) {
  CLI::App* field = app.add_subcommand("field", "Build a mesh's ObjectField into a .vfield file, or describe one");
  field->require_subcommand(1);

  auto build = std::make_shared<FieldBuildOptions>();
  CLI::App* b = field->add_subcommand("build", "Precompute the ObjectField of a mesh and write it to a .vfield file");
  add_scene_argument(*b, build->mesh);
  std::vector<CLI::Option*> resolution;
  for (const ParamSpec& param : field::kTableParams) {
    CLI::Option* option = add_param_option(*b, param, build->table[std::string(param.key)]);
    if (param.key == "positions" || param.key == "directions") resolution.push_back(option);
  }
  CLI::Option* target = b->add_option("--target-rms", build->target_rms,
                                      "E: choose positions and directions so that the AO image's RMS (0-255) against the exact one is "
                                      "expected to stay <= E (the calibration's field error model, 90% bound)")
                            ->check(number_in(0.01, 255.0));
  for (CLI::Option* option : resolution) target->excludes(option);
  b->add_option("--calibration", build->calibration, "Calibration file whose error model --target-rms uses (default: built in)")
      ->needs(target);
  b->add_option("-o,--out", build->out, "The .vfield file to write")->required();
  b->add_flag("--no-progress", build->no_progress, "Do not draw the progress bar");
  add_resource_options(*b, build->threads);
  b->callback([build, &action] { action = [build] { return run_field_build(*build); }; });

  auto file = std::make_shared<std::string>();
  CLI::App* i = field->add_subcommand("info", "Describe a .vfield file: parameters, sphere, mesh hash, memory, hit cells");
  i->add_option("file", *file, "The .vfield file")->required();
  i->callback([file, &action] { action = [file] { return run_field_info(*file); }; });
}

}  // namespace vf::cli
