// svo material: what a material JSON holds (its BRDF's parameters and
// directional albedo), and --export-merl, its BRDF tabulated in the MERL
// binary format, so that measured-BRDF rendering can be tried and tested
// without MERL's data (which no Debian package ships).
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "svo/render/merl.h"
#include "svo/render/shading.h"

namespace svo::tools {

void add_material_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "material",
      "Check a material JSON (DESIGN 10.2): print its BRDF and its directional albedo (white tint) at 0, 30, 60 and "
      "80 degrees; --export-merl writes the BRDF as a MERL binary (90x90x180 half/difference angles)");
  struct Args {
    std::string input, merl;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("FILE", a->input, "The material (.json)")->required();
  cmd->add_option("--export-merl", a->merl,
                  "Write the BRDF (diffuse part with a white tint plus the lobe) here, in MERL's binary format; "
                  "render it with {\"brdf\": \"merl\", \"file\": ...}");
  cmd->add_flag("--json", a->json, "Print one JSON object");
  cmd->callback([a, &exit_code] {
    const render::Material m = render::load_material(a->input);
    if (!a->merl.empty() && m.kind == render::BrdfKind::Merl) {
      throw std::invalid_argument(a->input + ": already a MERL BRDF (" + m.file.string() + ")");
    }
    const render::MaterialEvaluator eval(m);
    nlohmann::json albedo = nlohmann::json::object();
    for (int deg : {0, 30, 60, 80}) {
      const float t = float(deg) * 3.14159265f / 180.0f;
      const glm::vec3 a3 = eval.albedo(glm::vec3(1), glm::vec3(std::sin(t), 0, std::cos(t)), 1 << 16);
      albedo[std::to_string(deg)] = {a3.r, a3.g, a3.b};
    }
    if (!a->merl.empty()) {
      const render::MerlBrdf table = render::tabulate_merl([&](glm::dvec3 wi, glm::dvec3 wo) {
        return glm::dvec3(eval.brdf(glm::vec3(1), glm::vec3(wi), glm::vec3(wo)));
      });
      render::write_merl(a->merl, table);
    }
    if (a->json) {
      nlohmann::json out = nlohmann::json::parse(render::material_json(m));
      out["albedo"] = albedo;
      if (!a->merl.empty()) out["merl"] = a->merl;
      std::cout << out.dump() << "\n";
    } else {
      std::cout << a->input << ": " << render::material_json(m) << "\n";
      for (const auto& [deg, v] : albedo.items()) {
        std::printf("  albedo at %2s degrees: %.4f %.4f %.4f\n", deg.c_str(), v[0].get<double>(), v[1].get<double>(),
                    v[2].get<double>());
      }
      if (!a->merl.empty()) std::cout << "  wrote " << a->merl << " (MERL binary)\n";
    }
    exit_code = 0;
  });
}

}  // namespace svo::tools
