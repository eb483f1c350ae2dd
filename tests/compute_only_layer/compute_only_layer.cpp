// VK_LAYER_PROBEFILTER_compute_only: a test layer that reports every queue family without
// VK_QUEUE_GRAPHICS_BIT, so that a device which has only graphics-and-compute families (lavapipe)
// stands in for one with an engine's async compute queue. Enabled below the validation layer, it
// makes that layer judge every command, stage and access against a compute-only queue. Everything
// else passes through; the driver runs the work as before. One instance and one device at a time,
// as the tests use it.
#include <cstring>

#include <vulkan/vk_layer.h>
#include <vulkan/vulkan.h>

namespace {

PFN_vkGetInstanceProcAddr nextInstanceProcAddr = nullptr;
PFN_vkGetDeviceProcAddr nextDeviceProcAddr = nullptr;
PFN_vkGetPhysicalDeviceQueueFamilyProperties nextQueueFamilies = nullptr;
PFN_vkGetPhysicalDeviceQueueFamilyProperties2 nextQueueFamilies2 = nullptr;

// The loader's link to the next layer, in a create info's pNext chain.
template <typename LinkInfo, typename CreateInfo>
LinkInfo* findLink(const CreateInfo* info, VkStructureType type) {
    auto* link = static_cast<LinkInfo*>(const_cast<void*>(info->pNext));
    while (link && !(link->sType == type && link->function == VK_LAYER_LINK_INFO))
        link = static_cast<LinkInfo*>(const_cast<void*>(link->pNext));
    return link;
}

VKAPI_ATTR VkResult VKAPI_CALL createInstance(const VkInstanceCreateInfo* info, const VkAllocationCallbacks* allocator,
                                              VkInstance* instance) {
    auto* link = findLink<VkLayerInstanceCreateInfo>(info, VK_STRUCTURE_TYPE_LOADER_INSTANCE_CREATE_INFO);
    if (!link) return VK_ERROR_INITIALIZATION_FAILED;
    nextInstanceProcAddr = link->u.pLayerInfo->pfnNextGetInstanceProcAddr;
    link->u.pLayerInfo = link->u.pLayerInfo->pNext; // the next layer finds its own link
    auto create = reinterpret_cast<PFN_vkCreateInstance>(nextInstanceProcAddr(VK_NULL_HANDLE, "vkCreateInstance"));
    const VkResult result = create(info, allocator, instance);
    if (result != VK_SUCCESS) return result;
    nextQueueFamilies = reinterpret_cast<PFN_vkGetPhysicalDeviceQueueFamilyProperties>(
        nextInstanceProcAddr(*instance, "vkGetPhysicalDeviceQueueFamilyProperties"));
    nextQueueFamilies2 = reinterpret_cast<PFN_vkGetPhysicalDeviceQueueFamilyProperties2>(
        nextInstanceProcAddr(*instance, "vkGetPhysicalDeviceQueueFamilyProperties2"));
    return VK_SUCCESS;
}

VKAPI_ATTR VkResult VKAPI_CALL createDevice(VkPhysicalDevice physical, const VkDeviceCreateInfo* info,
                                            const VkAllocationCallbacks* allocator, VkDevice* device) {
    auto* link = findLink<VkLayerDeviceCreateInfo>(info, VK_STRUCTURE_TYPE_LOADER_DEVICE_CREATE_INFO);
    if (!link) return VK_ERROR_INITIALIZATION_FAILED;
    const PFN_vkGetInstanceProcAddr instanceProcAddr = link->u.pLayerInfo->pfnNextGetInstanceProcAddr;
    nextDeviceProcAddr = link->u.pLayerInfo->pfnNextGetDeviceProcAddr;
    link->u.pLayerInfo = link->u.pLayerInfo->pNext;
    auto create = reinterpret_cast<PFN_vkCreateDevice>(instanceProcAddr(VK_NULL_HANDLE, "vkCreateDevice"));
    return create(physical, info, allocator, device);
}

VKAPI_ATTR void VKAPI_CALL queueFamilies(VkPhysicalDevice physical, uint32_t* count, VkQueueFamilyProperties* families) {
    nextQueueFamilies(physical, count, families);
    for (uint32_t f = 0; families && f < *count; ++f) families[f].queueFlags &= ~VkQueueFlags(VK_QUEUE_GRAPHICS_BIT);
}

VKAPI_ATTR void VKAPI_CALL queueFamilies2(VkPhysicalDevice physical, uint32_t* count, VkQueueFamilyProperties2* families) {
    nextQueueFamilies2(physical, count, families);
    for (uint32_t f = 0; families && f < *count; ++f) families[f].queueFamilyProperties.queueFlags &= ~VkQueueFlags(VK_QUEUE_GRAPHICS_BIT);
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL getDeviceProcAddr(VkDevice device, const char* name) {
    if (std::strcmp(name, "vkGetDeviceProcAddr") == 0) return reinterpret_cast<PFN_vkVoidFunction>(getDeviceProcAddr);
    return nextDeviceProcAddr(device, name);
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL getInstanceProcAddr(VkInstance instance, const char* name) {
    if (std::strcmp(name, "vkGetInstanceProcAddr") == 0) return reinterpret_cast<PFN_vkVoidFunction>(getInstanceProcAddr);
    if (std::strcmp(name, "vkCreateInstance") == 0) return reinterpret_cast<PFN_vkVoidFunction>(createInstance);
    if (std::strcmp(name, "vkCreateDevice") == 0) return reinterpret_cast<PFN_vkVoidFunction>(createDevice);
    if (std::strcmp(name, "vkGetDeviceProcAddr") == 0) return reinterpret_cast<PFN_vkVoidFunction>(getDeviceProcAddr);
    if (std::strcmp(name, "vkGetPhysicalDeviceQueueFamilyProperties") == 0) return reinterpret_cast<PFN_vkVoidFunction>(queueFamilies);
    if (std::strcmp(name, "vkGetPhysicalDeviceQueueFamilyProperties2") == 0 ||
        std::strcmp(name, "vkGetPhysicalDeviceQueueFamilyProperties2KHR") == 0)
        return reinterpret_cast<PFN_vkVoidFunction>(queueFamilies2);
    return nextInstanceProcAddr ? nextInstanceProcAddr(instance, name) : nullptr;
}

} // namespace

// The one symbol the loader looks up (loader-layer interface version 2).
extern "C" VKAPI_ATTR VkResult VKAPI_CALL vkNegotiateLoaderLayerInterfaceVersion(VkNegotiateLayerInterface* version) {
    if (version->sType != LAYER_NEGOTIATE_INTERFACE_STRUCT || version->loaderLayerInterfaceVersion < 2)
        return VK_ERROR_INITIALIZATION_FAILED;
    version->loaderLayerInterfaceVersion = 2;
    version->pfnGetInstanceProcAddr = getInstanceProcAddr;
    version->pfnGetDeviceProcAddr = getDeviceProcAddr;
    version->pfnGetPhysicalDeviceProcAddr = nullptr;
    return VK_SUCCESS;
}
