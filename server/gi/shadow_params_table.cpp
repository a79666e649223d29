#include "gi/shadow_params_table.h"

#include <functional>
#include <sstream>

#include "core/flags.h"

namespace ddgi {
namespace {

using P = ShadowFieldParams;

struct Entry {
  ShadowParamInfo info;
  std::function<Status(P&, const std::string&)> set;
  std::function<std::string(const P&)> get;
};

std::string format(double v) {
  std::ostringstream out;
  out.precision(9);
  out << v;
  return out.str();
}

Result<std::vector<double>> parse_list(const std::string& name, const std::string& text) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    DDGI_ASSIGN_OR_RETURN(const double v, parse_double(item, name));
    values.push_back(v);
  }
  if (values.size() != 3) {
    return invalid_argument(name + " needs 3 comma-separated values (got '" + text + "')");
  }
  return values;
}

Entry float_entry(const char* name, const char* description, float P::*field) {
  return {{name, description},
          [=](P& p, const std::string& text) -> Status {
            DDGI_ASSIGN_OR_RETURN(const double v, parse_double(text, name));
            p.*field = static_cast<float>(v);
            return ok_status();
          },
          [=](const P& p) { return format(p.*field); }};
}

Entry uint_entry(const char* name, const char* description, uint32_t P::*field) {
  return {{name, description},
          [=](P& p, const std::string& text) -> Status {
            DDGI_ASSIGN_OR_RETURN(const int64_t v, parse_int(text, name));
            if (v < 0 || v > int64_t(UINT32_MAX)) {
              return invalid_argument(std::string(name) + " must be a non-negative integer");
            }
            p.*field = static_cast<uint32_t>(v);
            return ok_status();
          },
          [=](const P& p) { return std::to_string(p.*field); }};
}

Entry vec3_entry(const char* name, const char* description, glm::vec3 P::*field) {
  return {{name, description},
          [=](P& p, const std::string& text) -> Status {
            DDGI_ASSIGN_OR_RETURN(const auto v, parse_list(name, text));
            p.*field = glm::vec3(v[0], v[1], v[2]);
            return ok_status();
          },
          [=](const P& p) {
            const glm::vec3 v = p.*field;
            return format(v.x) + "," + format(v.y) + "," + format(v.z);
          }};
}

const std::vector<Entry>& entries() {
  static const std::vector<Entry> table = {
      vec3_entry("origin", "world position of probe (0,0,0); finite", &P::origin),
      vec3_entry("spacing", "distance between probes per axis; > 0", &P::spacing),
      {{"counts", "probes per axis, each in [1, 256], total <= 1048576"},
       [](P& p, const std::string& text) -> Status {
         DDGI_ASSIGN_OR_RETURN(const auto v, parse_list("counts", text));
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
      uint_entry("rays_per_probe", "probe rays per probe per update, [1, 1024]",
                 &P::rays_per_probe),
      uint_entry("max_lights", "lights kept in the atlas (first in scene order), [1, 8]",
                 &P::max_lights),
      {{"overflow", "lights past max_lights: shadow-rays | unshadowed"},
       [](P& p, const std::string& text) -> Status {
         if (text == "shadow-rays") {
           p.overflow = ShadowOverflow::kTracedShadows;
         } else if (text == "unshadowed") {
           p.overflow = ShadowOverflow::kUnshadowed;
         } else {
           return invalid_argument("overflow must be shadow-rays or unshadowed (got '" + text +
                                   "')");
         }
         return ok_status();
       },
       [](const P& p) {
         return std::string(p.overflow == ShadowOverflow::kUnshadowed ? "unshadowed"
                                                                      : "shadow-rays");
       }},
      {{"split_update", "shadow rays one update after their probe rays (thesis), on | off"},
       [](P& p, const std::string& text) -> Status {
         if (text == "on" || text == "true" || text == "1") {
           p.split_update = true;
         } else if (text == "off" || text == "false" || text == "0") {
           p.split_update = false;
         } else {
           return invalid_argument("split_update must be on or off (got '" + text + "')");
         }
         return ok_status();
       },
       [](const P& p) { return std::string(p.split_update ? "on" : "off"); }},
      float_entry("max_ray_distance", "longer probe rays see nothing, (0, 1e30]",
                  &P::max_ray_distance),
      float_entry("ao_distance", "longer AO rays count as open sky, (0, 1e30]", &P::ao_distance),
      uint_entry("texels", "octahedral map side, [4, 64]", &P::texels),
      float_entry("hysteresis", "history weight per update, [0, 0.999]", &P::hysteresis),
      float_entry("visibility_exponent", "power-cosine exponent of the visibility blend, [1, 1000]",
                  &P::visibility_exponent),
      float_entry("distance_exponent", "power-cosine exponent of the distance blend, [1, 1000]",
                  &P::distance_exponent),
      float_entry("backface_distance_scale", "back-face distance factor, [0, 1]",
                  &P::backface_distance_scale),
      {{"weighting", "probe weights when sampling: cosine | wrap"},
       [](P& p, const std::string& text) -> Status {
         if (text == "cosine") {
           p.weighting = ShadowWeighting::kCosine;
         } else if (text == "wrap") {
           p.weighting = ShadowWeighting::kWrap;
         } else {
           return invalid_argument("weighting must be cosine or wrap (got '" + text + "')");
         }
         return ok_status();
       },
       [](const P& p) {
         return std::string(p.weighting == ShadowWeighting::kWrap ? "wrap" : "cosine");
       }},
      float_entry("normal_bias", "shading-point offset along the normal (x spacing), [0, 1]",
                  &P::normal_bias),
      float_entry("view_bias", "shading-point offset towards the viewer (x spacing), [0, 1]",
                  &P::view_bias),
      float_entry("sharpening", "power applied to sampled visibility, [1, 16]", &P::sharpening),
      float_entry("weight_crush_threshold", "probe weights below are crushed, [0, 1]",
                  &P::weight_crush_threshold),
      uint_entry("seed", "seed of the ray rotations and jitter", &P::seed),
  };
  return table;
}

const Entry* find(const std::string& name) {
  for (const Entry& e : entries()) {
    if (e.info.name == name) return &e;
  }
  return nullptr;
}

Error unknown(const std::string& name) {
  std::string names;
  for (const Entry& e : entries()) names += (names.empty() ? "" : ", ") + e.info.name;
  return invalid_argument("unknown shadow field parameter '" + name + "' (known: " + names + ")");
}

}  // namespace

const std::vector<ShadowParamInfo>& shadow_param_infos() {
  static const std::vector<ShadowParamInfo> infos = [] {
    std::vector<ShadowParamInfo> v;
    for (const Entry& e : entries()) v.push_back(e.info);
    return v;
  }();
  return infos;
}

Status set_shadow_param(ShadowFieldParams& params, const std::string& name,
                        const std::string& value) {
  const Entry* e = find(name);
  if (!e) return unknown(name);
  return e->set(params, value);
}

Result<std::string> get_shadow_param(const ShadowFieldParams& params, const std::string& name) {
  const Entry* e = find(name);
  if (!e) return unknown(name);
  return e->get(params);
}

Status apply_shadow_assignments(ShadowFieldParams& params,
                                const std::vector<std::string>& assignments) {
  ShadowFieldParams updated = params;
  for (const std::string& a : assignments) {
    const size_t eq = a.find('=');
    if (eq == std::string::npos) {
      return invalid_argument("shadow field assignment '" + a + "' is not name=value");
    }
    DDGI_TRY(set_shadow_param(updated, a.substr(0, eq), a.substr(eq + 1)));
  }
  DDGI_TRY(validate(updated));
  params = updated;
  return ok_status();
}

}  // namespace ddgi
