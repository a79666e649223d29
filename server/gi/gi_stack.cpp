// The GI stack (gi/gi_stack.h).
#include "gi/gi_stack.h"

#include "gi/field_params.h"
#include "gi/shadow_params.h"

namespace ddgi {

Result<GiStackOptions> fitted_gi_options(const Scene& scene, bool gi, DirectMode direct_mode,
                                         const std::vector<std::string>& field_assignments,
                                         const std::vector<std::string>& shadow_assignments,
                                         vk::TraceBackend backend) {
  GiStackOptions options;
  options.gi = gi;
  options.direct_mode = direct_mode;
  options.backend = backend;
  options.field = default_field_params(scene);
  DDGI_TRY(field_param_table().apply(options.field, field_assignments));
  options.shadow = fit_shadow_grid(scene.world_bounds());
  DDGI_TRY(shadow_param_table().apply(options.shadow, shadow_assignments));
  return options;
}

Status validate(const GiUpdates& updates) {
  if (updates.field > 64) {
    return invalid_argument("field updates per frame must be in [0, 64] (got " +
                            std::to_string(updates.field) + ")");
  }
  if (updates.shadow_field > 64) {
    return invalid_argument("shadow field updates per frame must be in [0, 64] (got " +
                            std::to_string(updates.shadow_field) + ")");
  }
  return ok_status();
}

Result<std::vector<vk::Pass>> gi_update_passes(IrradianceField* field, ShadowField* shadow_field,
                                               DirectMode frame_mode, const GiUpdates& updates) {
  DDGI_TRY(validate(updates));
  std::vector<vk::Pass> passes;
  const DirectMode shadow_mode =
      shadow_field_mode(frame_mode, field && updates.field > 0 ? &field->params() : nullptr);
  if (shadow_field && uses_shadow_field(shadow_mode) && shadow_field->needs_update(shadow_mode)) {
    for (uint32_t i = 0; i < updates.shadow_field; ++i) {
      std::vector<vk::Pass> update = shadow_field->update_passes(shadow_mode);
      passes.insert(passes.end(), update.begin(), update.end());
    }
  }
  if (field && updates.field > 0) {
    DDGI_TRY(field->prepare());
    for (uint32_t i = 0; i < updates.field; ++i) {
      std::vector<vk::Pass> update = field->update_passes(frame_mode);
      passes.insert(passes.end(), update.begin(), update.end());
    }
  }
  return passes;
}

Result<std::unique_ptr<GiStack>> GiStack::create(vk::Context& context, const Scene& scene,
                                                 const GiStackOptions& options) {
  std::unique_ptr<GiStack> stack(new GiStack(options));
  DDGI_ASSIGN_OR_RETURN(stack->scene_, GpuScene::create(context, scene));
  if (uses_shadow_field(stack->shadow_update_mode(options.direct_mode))) {
    DDGI_ASSIGN_OR_RETURN(
        stack->shadow_field_,
        ShadowField::create(context, *stack->scene_, options.shadow, options.backend));
  }
  if (options.gi) {
    DDGI_ASSIGN_OR_RETURN(stack->field_,
                          IrradianceField::create(context, *stack->scene_, options.field,
                                                  options.backend, stack->shadow_field_.get()));
  }
  return stack;
}

DirectMode GiStack::shadow_update_mode(DirectMode frame_mode) const {
  return shadow_field_mode(frame_mode, options_.gi ? &options_.field : nullptr);
}

Status GiStack::update_shadow_field(uint32_t count) {
  const DirectMode mode = shadow_update_mode(options_.direct_mode);
  if (!shadow_field_ || count == 0 || !shadow_field_->needs_update(mode)) return ok_status();
  const auto times = shadow_field_->update(count, mode);
  return times.ok() ? ok_status() : Status(times.error());
}

Status GiStack::warm_up(uint32_t count) {
  DDGI_TRY(update_shadow_field(count));
  if (field_ && count > 0) DDGI_TRY(field_->warm_up(count, options_.direct_mode));
  return ok_status();
}

Status GiStack::update(uint32_t count) {
  DDGI_TRY(update_shadow_field(count));
  if (field_ && count > 0) {
    const auto times = field_->update(count, options_.direct_mode);
    if (!times.ok()) return times.error();
  }
  return ok_status();
}

}  // namespace ddgi
