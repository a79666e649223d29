#include "tests/gpu/field_setup.h"

#include <gtest/gtest.h>

#include "tests/gpu/gpu_test.h"

namespace ddgi::test {

FieldSetup make_field_setup(const Scene& scene, const IrradianceFieldParams& params,
                            vk::TraceBackend backend) {
  FieldSetup s;
  auto gpu = GpuScene::create(gpu_context(), scene);
  EXPECT_TRUE(gpu.ok()) << gpu.error().message;
  if (!gpu.ok()) return s;
  s.scene = std::move(gpu).value();
  auto field = IrradianceField::create(gpu_context(), *s.scene, params, backend);
  EXPECT_TRUE(field.ok()) << field.error().message;
  if (field.ok()) s.field = std::move(field).value();
  return s;
}

}  // namespace ddgi::test
