// Turns a failed Vulkan call into a ProbeError that names the call and the result code.
#pragma once

#include <vulkan/vulkan.h>

namespace probe::gpu {

const char* resultName(VkResult result);

// Throws ProbeError("Vulkan: <what> failed: <result>") unless result is VK_SUCCESS.
void vkCheck(VkResult result, const char* what);

} // namespace probe::gpu
