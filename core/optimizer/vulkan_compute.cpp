// Vulkan compute runner: dlopen'ed loader, one queue, one pipeline per kernel.
#define VK_NO_PROTOTYPES
#include "core/optimizer/vulkan_compute.h"

#include <dlfcn.h>
#include <vulkan/vulkan.h>

#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>

#include "core/error.h"

namespace c3d {
namespace {

// SPIR-V compiled from shaders/*.comp at build time (glslc -mfmt=num).
const uint32_t kOptEnergy[] = {
#include "opt_energy.spv.inc"
};
const uint32_t kOptTransform[] = {
#include "opt_transform.spv.inc"
};
const uint32_t kOptRefine[] = {
#include "opt_refine.spv.inc"
};
const uint32_t kOptSnapCurved[] = {
#include "opt_snap_curved.spv.inc"
};
const uint32_t kOptViewSelect[] = {
#include "opt_view_select.spv.inc"
};
const uint32_t kPointDistance[] = {
#include "point_distance.spv.inc"
};

struct Spirv {
  const uint32_t* code;
  size_t bytes;
};
const std::map<std::string, Spirv>& kernels() {
  static const std::map<std::string, Spirv> k = {
      {"opt_energy", {kOptEnergy, sizeof kOptEnergy}},
      {"opt_transform", {kOptTransform, sizeof kOptTransform}},
      {"opt_refine", {kOptRefine, sizeof kOptRefine}},
      {"opt_snap_curved", {kOptSnapCurved, sizeof kOptSnapCurved}},
      {"opt_view_select", {kOptViewSelect, sizeof kOptViewSelect}},
      {"point_distance", {kPointDistance, sizeof kPointDistance}},
  };
  return k;
}

#define C3D_VK_FUNCS(X)                                                                        \
  X(vkDestroyInstance) X(vkEnumeratePhysicalDevices) X(vkGetPhysicalDeviceProperties)          \
  X(vkGetPhysicalDeviceQueueFamilyProperties) X(vkGetPhysicalDeviceMemoryProperties)           \
  X(vkCreateDevice) X(vkDestroyDevice) X(vkGetDeviceQueue) X(vkCreateBuffer)                   \
  X(vkDestroyBuffer) X(vkGetBufferMemoryRequirements) X(vkAllocateMemory) X(vkFreeMemory)      \
  X(vkBindBufferMemory) X(vkMapMemory) X(vkUnmapMemory) X(vkCreateShaderModule)                \
  X(vkDestroyShaderModule) X(vkCreateDescriptorSetLayout) X(vkDestroyDescriptorSetLayout)      \
  X(vkCreatePipelineLayout) X(vkDestroyPipelineLayout) X(vkCreateComputePipelines)             \
  X(vkDestroyPipeline) X(vkCreateDescriptorPool) X(vkDestroyDescriptorPool)                    \
  X(vkAllocateDescriptorSets) X(vkUpdateDescriptorSets) X(vkCreateCommandPool)                 \
  X(vkDestroyCommandPool) X(vkAllocateCommandBuffers) X(vkResetCommandPool)                    \
  X(vkBeginCommandBuffer) X(vkEndCommandBuffer) X(vkCmdBindPipeline)                           \
  X(vkCmdBindDescriptorSets) X(vkCmdPushConstants) X(vkCmdDispatch) X(vkCmdCopyBuffer)         \
  X(vkCmdPipelineBarrier) X(vkQueueSubmit) X(vkQueueWaitIdle) X(vkInvalidateMappedMemoryRanges) \
  X(vkFlushMappedMemoryRanges)

struct Api {
  void* lib = nullptr;
  PFN_vkGetInstanceProcAddr getInstanceProcAddr = nullptr;
  PFN_vkCreateInstance vkCreateInstance = nullptr;
#define C3D_DECL(f) PFN_##f f = nullptr;
  C3D_VK_FUNCS(C3D_DECL)
#undef C3D_DECL
};

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw std::runtime_error(std::string(what) + " failed (VkResult " +
                                                std::to_string(static_cast<int>(r)) + ")");
}

}  // namespace

struct VulkanCompute::Impl {
  Api vk;
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice gpu = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties props{};
  VkPhysicalDeviceMemoryProperties mem{};
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t family = 0;
  VkCommandPool pool = VK_NULL_HANDLE;
  std::string name;
  std::mutex mutex;  // one run at a time on the single queue

  struct Pipeline {
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
    size_t bindings = 0;
  };
  std::map<std::string, Pipeline> pipelines;

  struct Buffer {
    VkBuffer buf = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize size = 0;
    bool host_coherent = false;
  };

  ~Impl() {
    if (device) {
      for (auto& [n, p] : pipelines) {
        vk.vkDestroyPipeline(device, p.pipeline, nullptr);
        vk.vkDestroyPipelineLayout(device, p.layout, nullptr);
        vk.vkDestroyDescriptorSetLayout(device, p.set_layout, nullptr);
      }
      if (pool) vk.vkDestroyCommandPool(device, pool, nullptr);
      vk.vkDestroyDevice(device, nullptr);
    }
    if (instance) vk.vkDestroyInstance(instance, nullptr);
    if (vk.lib) dlclose(vk.lib);
  }

  void load_loader() {
    vk.lib = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!vk.lib) throw std::runtime_error("no Vulkan loader (libvulkan.so.1 not found)");
    vk.getInstanceProcAddr =
        reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(vk.lib, "vkGetInstanceProcAddr"));
    if (!vk.getInstanceProcAddr) throw std::runtime_error("Vulkan loader lacks vkGetInstanceProcAddr");
    vk.vkCreateInstance = reinterpret_cast<PFN_vkCreateInstance>(
        vk.getInstanceProcAddr(VK_NULL_HANDLE, "vkCreateInstance"));
  }

  void create_instance() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "cadastre3d";
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ci.pApplicationInfo = &app;
    check(vk.vkCreateInstance(&ci, nullptr, &instance), "vkCreateInstance");
#define C3D_LOAD(f)                                                                  \
  vk.f = reinterpret_cast<PFN_##f>(vk.getInstanceProcAddr(instance, #f));            \
  if (!vk.f) throw std::runtime_error("Vulkan loader lacks " #f);
    C3D_VK_FUNCS(C3D_LOAD)
#undef C3D_LOAD
  }

  static int rank(VkPhysicalDeviceType t) {
    switch (t) {
      case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
      case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
      case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
      case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
      default: return 0;
    }
  }

  void pick_device() {
    uint32_t n = 0;
    check(vk.vkEnumeratePhysicalDevices(instance, &n, nullptr), "vkEnumeratePhysicalDevices");
    if (n == 0) throw std::runtime_error("no Vulkan physical device");
    std::vector<VkPhysicalDevice> devs(n);
    check(vk.vkEnumeratePhysicalDevices(instance, &n, devs.data()), "vkEnumeratePhysicalDevices");
    int best = -1;
    for (VkPhysicalDevice d : devs) {
      VkPhysicalDeviceProperties p;
      vk.vkGetPhysicalDeviceProperties(d, &p);
      int fam = compute_family(d);
      if (fam < 0 || rank(p.deviceType) <= best) continue;
      best = rank(p.deviceType);
      gpu = d;
      props = p;
      family = static_cast<uint32_t>(fam);
    }
    if (!gpu) throw std::runtime_error("no Vulkan device with a compute queue");
    vk.vkGetPhysicalDeviceMemoryProperties(gpu, &mem);
    name = props.deviceName;
  }

  int compute_family(VkPhysicalDevice d) const {
    uint32_t n = 0;
    vk.vkGetPhysicalDeviceQueueFamilyProperties(d, &n, nullptr);
    std::vector<VkQueueFamilyProperties> f(n);
    vk.vkGetPhysicalDeviceQueueFamilyProperties(d, &n, f.data());
    for (uint32_t i = 0; i < n; ++i)
      if (f[i].queueFlags & VK_QUEUE_COMPUTE_BIT) return static_cast<int>(i);
    return -1;
  }

  void create_device() {
    float prio = 1.0f;
    VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    q.queueFamilyIndex = family;
    q.queueCount = 1;
    q.pQueuePriorities = &prio;
    VkDeviceCreateInfo ci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    ci.queueCreateInfoCount = 1;
    ci.pQueueCreateInfos = &q;
    check(vk.vkCreateDevice(gpu, &ci, nullptr, &device), "vkCreateDevice");
    vk.vkGetDeviceQueue(device, family, 0, &queue);
    VkCommandPoolCreateInfo pc{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pc.queueFamilyIndex = family;
    check(vk.vkCreateCommandPool(device, &pc, nullptr, &pool), "vkCreateCommandPool");
  }

  int memory_type(uint32_t bits, VkMemoryPropertyFlags want) const {
    for (uint32_t i = 0; i < mem.memoryTypeCount; ++i)
      if ((bits & (1u << i)) && (mem.memoryTypes[i].propertyFlags & want) == want)
        return static_cast<int>(i);
    return -1;
  }

  // Device-local when possible; host-visible device-local memory (lavapipe,
  // integrated GPUs, resizable BAR) is used directly, otherwise via staging.
  Buffer make_buffer(VkDeviceSize size, VkBufferUsageFlags usage, bool host) {
    Buffer b;
    b.size = size < 16 ? 16 : size;
    VkBufferCreateInfo ci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    ci.size = b.size;
    ci.usage = usage;
    check(vk.vkCreateBuffer(device, &ci, nullptr, &b.buf), "vkCreateBuffer");
    VkMemoryRequirements req;
    vk.vkGetBufferMemoryRequirements(device, b.buf, &req);
    int type = -1;
    if (host) {
      type = memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                                 VK_MEMORY_PROPERTY_HOST_COHERENT_BIT |
                                                 VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
      if (type < 0)
        type = memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                                   VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
      b.host_coherent = true;
    } else {
      type = memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    }
    if (type < 0) {
      vk.vkDestroyBuffer(device, b.buf, nullptr);
      throw std::runtime_error("no suitable Vulkan memory type");
    }
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = static_cast<uint32_t>(type);
    VkResult r = vk.vkAllocateMemory(device, &ai, nullptr, &b.memory);
    if (r != VK_SUCCESS) vk.vkDestroyBuffer(device, b.buf, nullptr);
    check(r, "vkAllocateMemory");
    check(vk.vkBindBufferMemory(device, b.buf, b.memory, 0), "vkBindBufferMemory");
    return b;
  }

  void free_buffer(Buffer& b) {
    if (b.buf) vk.vkDestroyBuffer(device, b.buf, nullptr);
    if (b.memory) vk.vkFreeMemory(device, b.memory, nullptr);
    b = Buffer{};
  }

  // True when the device-local memory is also host-visible: no staging needed.
  bool unified_memory() const {
    for (uint32_t i = 0; i < mem.memoryTypeCount; ++i) {
      auto f = mem.memoryTypes[i].propertyFlags;
      if ((f & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) && (f & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) &&
          (f & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT))
        return props.deviceType != VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU;
    }
    return false;
  }

  Pipeline& pipeline(const std::string& kernel, size_t bindings) {
    auto it = pipelines.find(kernel);
    if (it != pipelines.end()) {
      if (it->second.bindings != bindings)
        throw std::logic_error("kernel " + kernel + " called with a different binding count");
      return it->second;
    }
    auto k = kernels().find(kernel);
    if (k == kernels().end()) throw std::logic_error("unknown kernel " + kernel);
    Pipeline p;
    p.bindings = bindings;
    std::vector<VkDescriptorSetLayoutBinding> b(bindings);
    for (size_t i = 0; i < bindings; ++i)
      b[i] = {static_cast<uint32_t>(i), VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
              VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo dl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    dl.bindingCount = static_cast<uint32_t>(bindings);
    dl.pBindings = b.data();
    check(vk.vkCreateDescriptorSetLayout(device, &dl, nullptr, &p.set_layout),
          "vkCreateDescriptorSetLayout");
    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, 128};
    VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pl.setLayoutCount = 1;
    pl.pSetLayouts = &p.set_layout;
    pl.pushConstantRangeCount = 1;
    pl.pPushConstantRanges = &range;
    check(vk.vkCreatePipelineLayout(device, &pl, nullptr, &p.layout), "vkCreatePipelineLayout");
    VkShaderModuleCreateInfo sm{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    sm.codeSize = k->second.bytes;
    sm.pCode = k->second.code;
    VkShaderModule module;
    check(vk.vkCreateShaderModule(device, &sm, nullptr, &module), "vkCreateShaderModule");
    VkComputePipelineCreateInfo cp{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cp.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    cp.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cp.stage.module = module;
    cp.stage.pName = "main";
    cp.layout = p.layout;
    VkResult r = vk.vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &cp, nullptr, &p.pipeline);
    vk.vkDestroyShaderModule(device, module, nullptr);
    check(r, "vkCreateComputePipelines");
    return pipelines.emplace(kernel, p).first->second;
  }

  void run(const std::string& kernel, const std::vector<GpuBuffer>& args, const void* push,
           uint32_t push_bytes, uint64_t threads);

  // The steps of run(), sharing its buffers: host[i] is mapped memory,
  // dev[i] the device-local copy when memory is not unified (staged).
  struct Dispatch {
    const std::vector<GpuBuffer>& args;
    bool staged;
    std::vector<Buffer> host, dev;
    VkDescriptorPool dpool = VK_NULL_HANDLE;
  };
  void upload(Dispatch& d);
  VkDescriptorSet bind_buffers(Dispatch& d, const Pipeline& p);
  VkCommandBuffer record(const Dispatch& d, const Pipeline& p, VkDescriptorSet set,
                         const void* push, uint32_t push_bytes, uint64_t threads);
  void submit_and_read_back(const Dispatch& d, VkCommandBuffer cmd);
};

void VulkanCompute::Impl::run(const std::string& kernel, const std::vector<GpuBuffer>& args,
                              const void* push, uint32_t push_bytes, uint64_t threads) {
  if (threads == 0) return;
  if (push_bytes > 128 || push_bytes % 4) throw std::logic_error("bad push-constant size");
  std::lock_guard<std::mutex> lock(mutex);
  Pipeline& p = pipeline(kernel, args.size());
  Dispatch d{args, !unified_memory(), std::vector<Buffer>(args.size()),
             std::vector<Buffer>(args.size())};
  auto cleanup = [&] {
    for (auto& b : d.host) free_buffer(b);
    for (auto& b : d.dev) free_buffer(b);
    if (d.dpool) vk.vkDestroyDescriptorPool(device, d.dpool, nullptr);
  };
  try {
    upload(d);
    VkDescriptorSet set = bind_buffers(d, p);
    VkCommandBuffer cmd = record(d, p, set, push, push_bytes, threads);
    submit_and_read_back(d, cmd);
  } catch (...) {
    cleanup();
    throw;
  }
  cleanup();
}

// Host-visible buffers filled with the arguments (and device buffers when staged).
void VulkanCompute::Impl::upload(Dispatch& d) {
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  for (size_t i = 0; i < d.args.size(); ++i) {
    d.host[i] = make_buffer(d.args[i].bytes, usage, true);
    if (d.staged) d.dev[i] = make_buffer(d.args[i].bytes, usage, false);
    void* map = nullptr;
    check(vk.vkMapMemory(device, d.host[i].memory, 0, VK_WHOLE_SIZE, 0, &map), "vkMapMemory");
    if (d.args[i].bytes) std::memcpy(map, d.args[i].data, d.args[i].bytes);
    vk.vkUnmapMemory(device, d.host[i].memory);
  }
}

// One descriptor set binding buffer i to binding i.
VkDescriptorSet VulkanCompute::Impl::bind_buffers(Dispatch& d, const Pipeline& p) {
  VkDescriptorPoolSize ps{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, static_cast<uint32_t>(d.args.size())};
  VkDescriptorPoolCreateInfo dp{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  dp.maxSets = 1;
  dp.poolSizeCount = 1;
  dp.pPoolSizes = &ps;
  check(vk.vkCreateDescriptorPool(device, &dp, nullptr, &d.dpool), "vkCreateDescriptorPool");
  VkDescriptorSetAllocateInfo da{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  da.descriptorPool = d.dpool;
  da.descriptorSetCount = 1;
  da.pSetLayouts = &p.set_layout;
  VkDescriptorSet set;
  check(vk.vkAllocateDescriptorSets(device, &da, &set), "vkAllocateDescriptorSets");
  std::vector<VkDescriptorBufferInfo> infos(d.args.size());
  std::vector<VkWriteDescriptorSet> writes(d.args.size());
  for (size_t i = 0; i < d.args.size(); ++i) {
    infos[i] = {d.staged ? d.dev[i].buf : d.host[i].buf, 0, VK_WHOLE_SIZE};
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = static_cast<uint32_t>(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vk.vkUpdateDescriptorSets(device, static_cast<uint32_t>(writes.size()), writes.data(), 0,
                            nullptr);
  return set;
}

// Copy in (when staged), dispatch, copy out of the buffers read back.
VkCommandBuffer VulkanCompute::Impl::record(const Dispatch& d, const Pipeline& p,
                                            VkDescriptorSet set, const void* push,
                                            uint32_t push_bytes, uint64_t threads) {
  check(vk.vkResetCommandPool(device, pool, 0), "vkResetCommandPool");
  VkCommandBufferAllocateInfo ca{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ca.commandPool = pool;
  ca.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ca.commandBufferCount = 1;
  VkCommandBuffer cmd;
  check(vk.vkAllocateCommandBuffers(device, &ca, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vk.vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  if (d.staged) {
    for (size_t i = 0; i < d.args.size(); ++i) {
      VkBufferCopy region{0, 0, d.host[i].size};
      vk.vkCmdCopyBuffer(cmd, d.host[i].buf, d.dev[i].buf, 1, &region);
    }
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
    vk.vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &barrier, 0, nullptr, 0,
                            nullptr);
  }
  vk.vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline);
  vk.vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout, 0, 1, &set, 0,
                             nullptr);
  if (push_bytes) vk.vkCmdPushConstants(cmd, p.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes, push);
  // Kernels use 64 threads per group and a 2-D grid past 65535 groups.
  const uint64_t groups = (threads + 63) / 64;
  const uint32_t gx = static_cast<uint32_t>(groups < 65535 ? groups : 65535);
  const uint32_t gy = static_cast<uint32_t>((groups + gx - 1) / gx);
  vk.vkCmdDispatch(cmd, gx, gy, 1);
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  barrier.dstAccessMask = d.staged ? VK_ACCESS_TRANSFER_READ_BIT : VK_ACCESS_HOST_READ_BIT;
  vk.vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                          d.staged ? VK_PIPELINE_STAGE_TRANSFER_BIT : VK_PIPELINE_STAGE_HOST_BIT, 0,
                          1, &barrier, 0, nullptr, 0, nullptr);
  if (d.staged) {
    for (size_t i = 0; i < d.args.size(); ++i) {
      if (!d.args[i].read_back) continue;
      VkBufferCopy region{0, 0, d.host[i].size};
      vk.vkCmdCopyBuffer(cmd, d.dev[i].buf, d.host[i].buf, 1, &region);
    }
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vk.vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0,
                            1, &barrier, 0, nullptr, 0, nullptr);
  }
  check(vk.vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  return cmd;
}

void VulkanCompute::Impl::submit_and_read_back(const Dispatch& d, VkCommandBuffer cmd) {
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  check(vk.vkQueueSubmit(queue, 1, &si, VK_NULL_HANDLE), "vkQueueSubmit");
  check(vk.vkQueueWaitIdle(queue), "vkQueueWaitIdle");
  for (size_t i = 0; i < d.args.size(); ++i) {
    if (!d.args[i].read_back || !d.args[i].bytes) continue;
    void* map = nullptr;
    check(vk.vkMapMemory(device, d.host[i].memory, 0, VK_WHOLE_SIZE, 0, &map), "vkMapMemory");
    std::memcpy(d.args[i].data, map, d.args[i].bytes);
    vk.vkUnmapMemory(device, d.host[i].memory);
  }
}

VulkanCompute::VulkanCompute(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
VulkanCompute::~VulkanCompute() = default;

std::unique_ptr<VulkanCompute> VulkanCompute::create(std::string* why) {
  auto impl = std::make_unique<Impl>();
  try {
    impl->load_loader();
    impl->create_instance();
    impl->pick_device();
    impl->create_device();
  } catch (const std::exception& e) {
    if (why) *why = e.what();
    return nullptr;
  }
  return std::unique_ptr<VulkanCompute>(new VulkanCompute(std::move(impl)));
}

const std::string& VulkanCompute::device_name() const { return impl_->name; }

const char* VulkanCompute::device_type() const {
  switch (impl_->props.deviceType) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU (software Vulkan)";
    default: return "other";
  }
}

void VulkanCompute::run(const std::string& kernel, const std::vector<GpuBuffer>& buffers,
                        const void* push, std::uint32_t push_bytes, std::uint64_t threads) {
  impl_->run(kernel, buffers, push, push_bytes, threads);
}

VulkanCompute* shared_vulkan(std::string* why) {
  static std::string reason;
  static std::unique_ptr<VulkanCompute> runner = VulkanCompute::create(&reason);
  if (!runner && why) *why = reason;
  return runner.get();
}

ComputeDevice parse_compute_device(const std::string& name) {
  if (name == "auto") return ComputeDevice::Auto;
  if (name == "cpu") return ComputeDevice::Cpu;
  if (name == "vulkan") return ComputeDevice::Vulkan;
  throw InputError("--device", "expected cpu, vulkan or auto, got '" + name + "'");
}

VulkanCompute* select_compute(ComputeDevice device, std::string* note) {
  if (device == ComputeDevice::Cpu) {
    if (note) *note = "CPU reference (requested)";
    return nullptr;
  }
  std::string why;
  VulkanCompute* vk = shared_vulkan(&why);
  if (note) {
    *note = vk ? "Vulkan: " + vk->device_name() + " (" + vk->device_type() + ")"
               : "CPU reference (Vulkan unavailable: " + why + ")";
  }
  return vk;
}

}  // namespace c3d
