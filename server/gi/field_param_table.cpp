#include "gi/field_param_table.h"

#include <functional>
#include <sstream>

#include "core/flags.h"

namespace ddgi {
namespace {

struct Entry {
  FieldParamInfo info;
  std::function<Status(IrradianceFieldParams&, const std::string&)> set;
  std::function<std::string(const IrradianceFieldParams&)> get;
};

Result<std::vector<double>> parse_list(const std::string& name, const std::string& text,
                                       size_t count) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    DDGI_ASSIGN_OR_RETURN(const double v, parse_double(item, name));
    values.push_back(v);
  }
  if (values.size() != count) {
    return invalid_argument(name + " needs " + std::to_string(count) +
                            " comma-separated values (got '" + text + "')");
  }
  return values;
}

std::string format(double v) {
  std::ostringstream out;
  out.precision(9);
  out << v;
  return out.str();
}

Entry float_entry(const char* name, const char* description, float IrradianceFieldParams::*field) {
  return {{name, description},
          [=](IrradianceFieldParams& p, const std::string& text) -> Status {
            DDGI_ASSIGN_OR_RETURN(const double v, parse_double(text, name));
            p.*field = static_cast<float>(v);
            return ok_status();
          },
          [=](const IrradianceFieldParams& p) { return format(p.*field); }};
}

Entry uint_entry(const char* name, const char* description,
                 uint32_t IrradianceFieldParams::*field) {
  return {{name, description},
          [=](IrradianceFieldParams& p, const std::string& text) -> Status {
            DDGI_ASSIGN_OR_RETURN(const int64_t v, parse_int(text, name));
            if (v < 0 || v > int64_t(UINT32_MAX)) {
              return invalid_argument(std::string(name) + " must be a non-negative integer");
            }
            p.*field = static_cast<uint32_t>(v);
            return ok_status();
          },
          [=](const IrradianceFieldParams& p) { return std::to_string(p.*field); }};
}

Entry vec3_entry(const char* name, const char* description,
                 glm::vec3 IrradianceFieldParams::*field) {
  return {{name, description},
          [=](IrradianceFieldParams& p, const std::string& text) -> Status {
            DDGI_ASSIGN_OR_RETURN(const auto v, parse_list(name, text, 3));
            p.*field = glm::vec3(v[0], v[1], v[2]);
            return ok_status();
          },
          [=](const IrradianceFieldParams& p) {
            const glm::vec3 v = p.*field;
            return format(v.x) + "," + format(v.y) + "," + format(v.z);
          }};
}

const std::vector<Entry>& entries() {
  using P = IrradianceFieldParams;
  static const std::vector<Entry> table = {
      vec3_entry("origin", "world position of probe (0,0,0); finite", &P::origin),
      vec3_entry("spacing", "distance between probes per axis; > 0", &P::spacing),
      {{"counts", "probes per axis, each in [1, 512], total <= 4194304"},
       [](P& p, const std::string& text) -> Status {
         DDGI_ASSIGN_OR_RETURN(const auto v, parse_list("counts", text, 3));
         for (double c : v) {
           if (c != double(int64_t(c)) || c < 0 || c > 1e6) {
             return invalid_argument("counts must be three integers (got '" + text + "')");
           }
         }
         p.counts = glm::ivec3(int(v[0]), int(v[1]), int(v[2]));
         return ok_status();
       },
       [](const P& p) {
         return std::to_string(p.counts.x) + "," + std::to_string(p.counts.y) + "," +
                std::to_string(p.counts.z);
       }},
      uint_entry("rays_per_probe", "blended rays per probe per update, [1, 1024]",
                 &P::rays_per_probe),
      uint_entry("fixed_rays", "unrotated rays for relocation/classification, [0, 256]",
                 &P::fixed_rays),
      float_entry("max_ray_distance", "longer rays are misses, (0, 1e30]", &P::max_ray_distance),
      uint_entry("irradiance_texels", "irradiance map side, [4, 32]", &P::irradiance_texels),
      uint_entry("distance_texels", "distance map side, [4, 64]", &P::distance_texels),
      float_entry("hysteresis", "history weight per update, [0, 0.999]", &P::hysteresis),
      float_entry("distance_hysteresis", "history weight of distances, [0, 0.999]",
                  &P::distance_hysteresis),
      float_entry("change_threshold", "relative change that lowers hysteresis, [0, 1]",
                  &P::change_threshold),
      float_entry("new_distribution_threshold", "relative change that drops history, [0, 1]",
                  &P::new_distribution_threshold),
      float_entry("irradiance_gamma", "perceptual encoding exponent, [1, 10]",
                  &P::irradiance_gamma),
      float_entry("distance_exponent", "power-cosine exponent of distances, [1, 100]",
                  &P::distance_exponent),
      float_entry("backface_distance_scale", "back-face distance factor, [0, 1]",
                  &P::backface_distance_scale),
      float_entry("self_shadow_bias", "2021 paper's B, [0, 2]", &P::self_shadow_bias),
      float_entry("energy_conservation", "irradiance feedback factor, [0, 1]",
                  &P::energy_conservation),
      float_entry("weight_crush_threshold", "weights below are crushed, [0, 1]",
                  &P::weight_crush_threshold),
      uint_entry("relocation_iterations", "relocation passes, [0, 16]; 0: no relocation",
                 &P::relocation_iterations),
      {{"classification",
        "true/false: Off/Sleeping/Vigilant/Awake states, trace active probes only"},
       [](P& p, const std::string& text) -> Status {
         if (text != "true" && text != "false") {
           return invalid_argument("classification must be true or false (got '" + text + "')");
         }
         p.classification = text == "true";
         return ok_status();
       },
       [](const P& p) { return std::string(p.classification ? "true" : "false"); }},
      float_entry("probe_offset_limit", "relocation limit, fraction of spacing, [0, 0.49]",
                  &P::probe_offset_limit),
      float_entry("min_frontface_distance", "relocation clearance, fraction of spacing, [0, 0.5]",
                  &P::min_frontface_distance),
      float_entry("backface_threshold", "back-face fraction meaning inside, (0, 1]",
                  &P::backface_threshold),
      {{"max_rays_per_update", "probe rays per update, 0: no cap, else >= one probe's rays"},
       [](P& p, const std::string& text) -> Status {
         DDGI_ASSIGN_OR_RETURN(const int64_t v, parse_int(text, "max_rays_per_update"));
         if (v < 0) return invalid_argument("max_rays_per_update must be >= 0");
         p.max_rays_per_update = static_cast<uint64_t>(v);
         return ok_status();
       },
       [](const P& p) { return std::to_string(p.max_rays_per_update); }},
      uint_entry("emitter_samples",
                 "emitter samples per pixel and probe-ray hit, [0, 64]; 0: emitters via the field",
                 &P::emitter_samples),
      {{"probe_direct",
        "direct light at probe-ray hits: frame (the frame's mode), shadow-rays, unshadowed, "
        "shadow-field or ao"},
       [](P& p, const std::string& text) -> Status {
         if (text == "frame") {
           p.probe_direct.reset();
           return ok_status();
         }
         auto mode = parse_direct_mode(text);
         if (!mode.ok()) {
           return invalid_argument(
               "probe_direct must be frame, shadow-rays, unshadowed, "
               "shadow-field or ao (got '" +
               text + "')");
         }
         p.probe_direct = *mode;
         return ok_status();
       },
       [](const P& p) {
         return std::string(p.probe_direct ? direct_mode_name(*p.probe_direct) : "frame");
       }},
      uint_entry("seed", "seed of the random ray rotations", &P::seed),
  };
  return table;
}

const Entry* find(const std::string& name) {
  for (const Entry& e : entries()) {
    if (e.info.name == name) return &e;
  }
  return nullptr;
}

std::string known_names() {
  std::string names;
  for (const Entry& e : entries()) names += (names.empty() ? "" : ", ") + e.info.name;
  return names;
}

}  // namespace

const std::vector<FieldParamInfo>& field_param_infos() {
  static const std::vector<FieldParamInfo> infos = [] {
    std::vector<FieldParamInfo> v;
    for (const Entry& e : entries()) v.push_back(e.info);
    return v;
  }();
  return infos;
}

Status set_field_param(IrradianceFieldParams& params, const std::string& name,
                       const std::string& value) {
  const Entry* e = find(name);
  if (!e)
    return invalid_argument("unknown field parameter '" + name + "' (known: " + known_names() +
                            ")");
  return e->set(params, value);
}

Result<std::string> get_field_param(const IrradianceFieldParams& params, const std::string& name) {
  const Entry* e = find(name);
  if (!e)
    return invalid_argument("unknown field parameter '" + name + "' (known: " + known_names() +
                            ")");
  return e->get(params);
}

Status apply_field_assignments(IrradianceFieldParams& params,
                               const std::vector<std::string>& assignments) {
  IrradianceFieldParams updated = params;
  for (const std::string& a : assignments) {
    const size_t eq = a.find('=');
    if (eq == std::string::npos) {
      return invalid_argument("field parameter assignment '" + a + "' is not name=value");
    }
    DDGI_TRY(set_field_param(updated, a.substr(0, eq), a.substr(eq + 1)));
  }
  DDGI_TRY(validate(updated));
  params = updated;
  return ok_status();
}

}  // namespace ddgi
