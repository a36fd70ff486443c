#pragma once
// A small Vulkan compute runner for the embedded kernels in shaders/*.comp.
// Vulkan is loaded at run time through the system loader (libvulkan.so.1), so
// a machine without a loader or a device still runs: create() returns nullptr
// with the reason and callers fall back to the CPU reference.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace c3d {

enum class ComputeDevice { Auto, Cpu, Vulkan };

// "auto" | "cpu" | "vulkan"; throws InputError on anything else.
ComputeDevice parse_compute_device(const std::string& name);

// Host memory bound to one storage-buffer binding (binding = position in the list).
struct GpuBuffer {
  void* data = nullptr;
  std::size_t bytes = 0;
  bool read_back = false;  // copy the device result back into data after the run
};

class VulkanCompute {
 public:
  // Picks a discrete GPU, else an integrated one, else any device with a compute
  // queue (lavapipe). nullptr and *why when there is no loader, instance or device.
  static std::unique_ptr<VulkanCompute> create(std::string* why);
  ~VulkanCompute();
  VulkanCompute(const VulkanCompute&) = delete;
  VulkanCompute& operator=(const VulkanCompute&) = delete;

  const std::string& device_name() const;
  const char* device_type() const;  // "discrete GPU", "integrated GPU", "CPU (software)", ...
  // Runs kernel `kernel` (file name of the shader without .comp) over `threads`
  // invocations and waits for it. push_bytes <= 128, a multiple of 4.
  void run(const std::string& kernel, const std::vector<GpuBuffer>& buffers, const void* push,
           std::uint32_t push_bytes, std::uint64_t threads);

 private:
  struct Impl;
  explicit VulkanCompute(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Process-wide runner, created on first use; nullptr (and *why) when unavailable.
VulkanCompute* shared_vulkan(std::string* why = nullptr);

// The runner for a device request: nullptr for Cpu; for Vulkan/Auto the shared
// runner or nullptr when unavailable (with *note saying why). Never throws.
VulkanCompute* select_compute(ComputeDevice device, std::string* note);

}  // namespace c3d
