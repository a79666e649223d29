// The descriptor sets, query kernel and parameter rule every probe field shares
// (gi/field_sets.h).
#include "gi/field_sets.h"

namespace ddgi {

Result<FieldSets> FieldSets::create(vk::Context& context, const GpuScene& scene,
                                    const FieldSetsDesc& desc, vk::TraceBackend backend) {
  if (desc.query.size() != 2) return internal_error(desc.name + ": a query set has two bindings");
  FieldSets s;
  s.context_ = &context;
  s.scene_ = &scene;
  s.desc_ = desc;
  DDGI_ASSIGN_OR_RETURN(
      s.sampling_layout_,
      vk::DescriptorLayout::create(context, desc.sampling, 1, desc.name + " sampling set"));
  DDGI_ASSIGN_OR_RETURN(s.update_layout_, vk::DescriptorLayout::create(context, desc.update, 1,
                                                                       desc.name + " update set"));
  DDGI_ASSIGN_OR_RETURN(s.query_layout_, vk::DescriptorLayout::create(context, desc.query, 1,
                                                                      desc.name + " query set"));
  DDGI_ASSIGN_OR_RETURN(s.sampling_set_, s.sampling_layout_.allocate());
  DDGI_ASSIGN_OR_RETURN(s.update_set_, s.update_layout_.allocate());
  DDGI_ASSIGN_OR_RETURN(s.query_set_, s.query_layout_.allocate());
  DDGI_ASSIGN_OR_RETURN(
      s.query_kernel_,
      vk::Kernel::create(context,
                         {desc.query_kernel,
                          desc.query_traces,
                          {scene.layout(), s.query_layout_.handle(), s.sampling_layout_.handle()},
                          desc.push_constant_bytes,
                          desc.workgroup},
                         backend));
  DDGI_ASSIGN_OR_RETURN(s.timer_, vk::GpuTimer::create(context, desc.timed_passes));
  DDGI_ASSIGN_OR_RETURN(
      s.sampler_,
      vk::Sampler::create(context, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                          VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, desc.name + " atlas sampler"));
  return s;
}

std::vector<VkDescriptorSetLayout> FieldSets::update_layouts() const {
  return {scene_->layout(), update_layout_.handle(), sampling_layout_.handle()};
}

Status FieldSets::run_query(const vk::Buffer& in, const vk::Buffer& out, uint32_t count,
                            const std::function<std::vector<uint8_t>(uint32_t, uint32_t)>& push,
                            std::vector<vk::Pass> before) {
  vk::DescriptorWriter(query_set_)
      .buffer(desc_.query[0].binding, in)
      .buffer(desc_.query[1].binding, out)
      .apply(context_->device());
  const vk::LinearDispatch d = vk::linear_dispatch(count);
  vk::Pass pass;
  pass.name = desc_.name + " query";
  pass.kernel = &query_kernel_;
  pass.sets = {scene_->descriptor_set(), query_set_, sampling_set_};
  pass.push_constants = push(count, d.row_width);
  pass.size = d.size;
  pass.reads = {&in};
  pass.writes = {&out};
  before.push_back(std::move(pass));
  return context_->submit_and_wait(
      [&](VkCommandBuffer cmd) { vk::record_passes(cmd, nullptr, before); });
}

}  // namespace ddgi
