// GI stacks for field tests (tests/gpu/field_setup.h).
#include "tests/gpu/field_setup.h"

#include <gtest/gtest.h>

#include "tests/gpu/gpu_test.h"

namespace ddgi::test {

FieldSetup make_field_setup(const Scene& scene, const IrradianceFieldParams& params,
                            vk::TraceBackend backend) {
  FieldSetup s;
  GiStackOptions options;
  options.field = params;
  options.backend = backend;
  auto gi = GiStack::create(gpu_context(), scene, options);
  EXPECT_TRUE(gi.ok()) << gi.error().message;
  if (!gi.ok()) return s;
  s.gi = std::move(gi).value();
  s.scene = &s.gi->scene();
  s.field = s.gi->field();
  return s;
}

Result<FrameResult> render_updated(Renderer& renderer, const FrameSettings& settings,
                                   IrradianceField* field, ShadowField* shadow_field,
                                   GiUpdates updates) {
  DDGI_ASSIGN_OR_RETURN(const std::vector<vk::Pass> passes,
                        gi_update_passes(field, shadow_field, settings.direct_mode, updates));
  return renderer.render(settings, passes);
}

}  // namespace ddgi::test
