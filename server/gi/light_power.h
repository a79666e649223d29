// How much light each kind of source puts into a scene: what the default field weighs to decide
// whether its emissive surfaces are worth sampling per pixel and per probe-ray hit
// (default_field_params), so that a scene lit by the sun with a few glowing signs does not pay
// two emitter rays per probe-ray hit for light it cannot show (the street: 2.2x the field time,
// the same image; docs/results/cascades.md).
#pragma once

#include "scene/scene.h"

namespace ddgi {

// Emitted flux per kind of source, luminance-weighted (Rec. 709 of each colour), in the scene's
// radiometric units (W). Estimates, made to favour the emitters where unsure: an emissive
// texture counts at its factor (texels are at most 1) and the environment is left out (how much
// of it enters is a matter of occlusion).
struct LightPower {
  double emitters = 0.0;     // emissive surfaces: pi x area x the emissive factor's luminance
  double punctual = 0.0;     // point lights 4 pi x intensity, spots their cone's solid angle x it
  double directional = 0.0;  // irradiance x the area the scene's bounds turn towards the light

  double total() const { return emitters + punctual + directional; }
};

LightPower light_power(const Scene& scene);

// Emitters sample by default when they put out at least this share of the scene's light. 0.05:
// far below every emitter-lit scene we have (1.0 where they are the only light), far above the
// street's signs under the sun.
inline constexpr double kEmitterShareToSample = 0.05;

// Whether the emitters of `scene` carry kEmitterShareToSample of its light or more.
bool emitters_worth_sampling(const Scene& scene);

}  // namespace ddgi
