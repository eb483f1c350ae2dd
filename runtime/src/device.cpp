// Device: instance and device creation, device choice, the validation layer's messages.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>

#include <fmt/format.h>

#include "device.h"
#include "probe/error.h"
#include "vulkan_check.h"

namespace probe::gpu {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

std::string typeName(VkPhysicalDeviceType type) {
    switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
    }
}

VkInstance createInstance(bool validation) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "probefilter";
    app.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    // Hazards between the passes, and against the engine's work, are errors too.
    const VkValidationFeatureEnableEXT enabled = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    const VkValidationFeaturesEXT synchronization{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT, nullptr, 1, &enabled, 0, nullptr};
    if (validation) {
        uint32_t count = 0;
        vkEnumerateInstanceLayerProperties(&count, nullptr);
        std::vector<VkLayerProperties> layers(count);
        vkEnumerateInstanceLayerProperties(&count, layers.data());
        if (std::none_of(layers.begin(), layers.end(),
                         [](const VkLayerProperties& l) { return std::strcmp(l.layerName, kValidationLayer) == 0; }))
            throw ProbeError(
                fmt::format("Vulkan: validation requested but {} is not installed (Debian: vulkan-validationlayers)", kValidationLayer));
        info.enabledLayerCount = 1;
        info.ppEnabledLayerNames = &kValidationLayer;
        info.enabledExtensionCount = 1;
        info.ppEnabledExtensionNames = &extension;
        info.pNext = &synchronization;
    }
    VkInstance instance = VK_NULL_HANDLE;
    const VkResult result = vkCreateInstance(&info, nullptr, &instance);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw ProbeError("Vulkan: no Vulkan 1.2 driver found (install Mesa's lavapipe, mesa-vulkan-drivers, or a GPU driver)");
    vkCheck(result, "vkCreateInstance");
    return instance;
}

VKAPI_ATTR VkBool32 VKAPI_CALL collectMessage(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* impl = static_cast<Device::Impl*>(user);
    const std::lock_guard lock(impl->messagesMutex);
    impl->messages.emplace_back(data->pMessage ? data->pMessage : "(no message)");
    return VK_FALSE;
}

VkDebugUtilsMessengerEXT createMessenger(VkInstance instance, Device::Impl* impl) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
    if (!create) throw ProbeError("Vulkan: VK_EXT_debug_utils is not available for the validation layer's messages");
    VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    info.pfnUserCallback = collectMessage;
    info.pUserData = impl;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    vkCheck(create(instance, &info, nullptr, &messenger), "vkCreateDebugUtilsMessengerEXT");
    return messenger;
}

// The first queue family with compute, or -1.
int computeQueueFamily(VkPhysicalDevice physical) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &count, families.data());
    for (uint32_t f = 0; f < count; ++f)
        if (families[f].queueFlags & VK_QUEUE_COMPUTE_BIT) return static_cast<int>(f);
    return -1;
}

struct Candidate {
    VkPhysicalDevice physical;
    DeviceInfo info;
};

std::vector<Candidate> usableDevices(VkInstance instance) {
    uint32_t count = 0;
    vkCheck(vkEnumeratePhysicalDevices(instance, &count, nullptr), "vkEnumeratePhysicalDevices");
    std::vector<VkPhysicalDevice> physicals(count);
    vkCheck(vkEnumeratePhysicalDevices(instance, &count, physicals.data()), "vkEnumeratePhysicalDevices");
    std::vector<Candidate> candidates;
    for (uint32_t i = 0; i < count; ++i) {
        VkPhysicalDeviceProperties properties;
        vkGetPhysicalDeviceProperties(physicals[i], &properties);
        if (properties.apiVersion < VK_API_VERSION_1_2 || computeQueueFamily(physicals[i]) < 0) continue;
        candidates.push_back({physicals[i], describePhysicalDevice(physicals[i], static_cast<int>(i))});
    }
    return candidates;
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

std::string listing(const std::vector<Candidate>& candidates) {
    std::string text;
    for (const Candidate& c : candidates)
        text += fmt::format("{}{}: {} ({})", text.empty() ? "" : "; ", c.info.index, c.info.name, c.info.type);
    return text.empty() ? "none" : text;
}

const Candidate& chooseDevice(const std::vector<Candidate>& candidates, const std::string& choice) {
    if (candidates.empty())
        throw ProbeError(
            "Vulkan: no device with Vulkan 1.2 and a compute queue (install Mesa's lavapipe, mesa-vulkan-drivers, or a GPU driver)");
    if (choice.empty()) {
        for (const char* type : {"discrete", "integrated", "virtual", "cpu"})
            for (const Candidate& c : candidates)
                if (c.info.type == type) return c;
        return candidates.front();
    }
    int index = -1;
    const auto [end, error] = std::from_chars(choice.data(), choice.data() + choice.size(), index);
    if (error == std::errc() && end == choice.data() + choice.size()) {
        for (const Candidate& c : candidates)
            if (c.info.index == index) return c;
        throw ParameterError("device", fmt::format("{}: no such Vulkan device (devices: {})", choice, listing(candidates)));
    }
    for (const Candidate& c : candidates)
        if (lower(c.info.name).find(lower(choice)) != std::string::npos) return c;
    throw ParameterError("device", fmt::format("{}: no Vulkan device of that name (devices: {})", choice, listing(candidates)));
}

void readProperties(Device::Impl& impl) {
    VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties.pNext = &subgroup;
    vkGetPhysicalDeviceProperties2(impl.physical, &properties);
    impl.limits = properties.properties.limits;
    impl.computeSubgroupVote =
        (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) && (subgroup.supportedOperations & VK_SUBGROUP_FEATURE_VOTE_BIT);
    vkGetPhysicalDeviceMemoryProperties(impl.physical, &impl.memory);
    for (VkFormat format :
         {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_B10G11R11_UFLOAT_PACK32, VK_FORMAT_R32_UINT}) {
        VkFormatProperties formatProperties;
        vkGetPhysicalDeviceFormatProperties(impl.physical, format, &formatProperties);
        impl.formatFeatures[format] = formatProperties.optimalTilingFeatures;
    }
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(impl.physical, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(impl.physical, &count, families.data());
    impl.timestampValidBits = impl.queueFamily < count ? families[impl.queueFamily].timestampValidBits : 0;
}

} // namespace

DeviceInfo describePhysicalDevice(VkPhysicalDevice physical, int index) {
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties.pNext = &driver;
    vkGetPhysicalDeviceProperties2(physical, &properties);
    DeviceInfo info;
    info.index = index;
    info.name = properties.properties.deviceName;
    info.driver = fmt::format("{}, {}", driver.driverName, driver.driverInfo);
    info.type = typeName(properties.properties.deviceType);
    info.apiVersion = properties.properties.apiVersion;
    return info;
}

VkFormatFeatureFlags Device::Impl::features(VkFormat format) const {
    if (const auto known = formatFeatures.find(format); known != formatFeatures.end()) return known->second;
    VkFormatProperties properties;
    vkGetPhysicalDeviceFormatProperties(physical, format, &properties);
    return properties.optimalTilingFeatures;
}

uint32_t Device::Impl::memoryType(uint32_t typeBits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) const {
    int fallback = -1;
    for (uint32_t t = 0; t < memory.memoryTypeCount; ++t) {
        if (!(typeBits & (1u << t))) continue;
        const VkMemoryPropertyFlags flags = memory.memoryTypes[t].propertyFlags;
        if ((flags & required) != required) continue;
        if ((flags & preferred) == preferred) return t;
        if (fallback < 0) fallback = static_cast<int>(t);
    }
    if (fallback < 0) throw ProbeError("Vulkan: no memory type for a buffer of the runtime");
    return static_cast<uint32_t>(fallback);
}

void Device::Impl::retire(std::shared_ptr<void> resources, VkSemaphore semaphore, uint64_t value) {
    retired.push_back({std::move(resources), semaphore, value});
}

void Device::Impl::releaseRetired() {
    std::erase_if(retired, [&](const Retired& r) {
        uint64_t value = 0;
        return vkGetSemaphoreCounterValue(device, r.semaphore, &value) == VK_SUCCESS && value >= r.value;
    });
}

std::vector<DeviceInfo> listDevices() {
    const VkInstance instance = createInstance(false);
    std::vector<DeviceInfo> infos;
    for (const Candidate& c : usableDevices(instance)) infos.push_back(c.info);
    vkDestroyInstance(instance, nullptr);
    return infos;
}

Device::Device(const DeviceOptions& options) : impl_(std::make_unique<Impl>()) {
    Impl& d = *impl_;
    d.owned = true;
    d.instance = createInstance(options.validation);
    try {
        if (options.validation) d.messenger = createMessenger(d.instance, &d);
        const std::vector<Candidate> candidates = usableDevices(d.instance);
        const Candidate& chosen = chooseDevice(candidates, options.choice);
        d.physical = chosen.physical;
        d.info = chosen.info;
        d.queueFamily = static_cast<uint32_t>(computeQueueFamily(d.physical));

        const float priority = 1.0f;
        VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        queueInfo.queueFamilyIndex = d.queueFamily;
        queueInfo.queueCount = 1;
        queueInfo.pQueuePriorities = &priority;
        VkPhysicalDeviceFeatures supported;
        vkGetPhysicalDeviceFeatures(d.physical, &supported);
        VkPhysicalDeviceFeatures enabled{};
        enabled.imageCubeArray = supported.imageCubeArray; // batches
        VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        features12.timelineSemaphore = VK_TRUE; // a Filter's Completion
        VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features12};
        deviceInfo.pEnabledFeatures = &enabled;
        deviceInfo.queueCreateInfoCount = 1;
        deviceInfo.pQueueCreateInfos = &queueInfo;
        vkCheck(vkCreateDevice(d.physical, &deviceInfo, nullptr, &d.device), "vkCreateDevice");
        vkGetDeviceQueue(d.device, d.queueFamily, 0, &d.queue);
        readProperties(d);
        d.imageCubeArray = enabled.imageCubeArray == VK_TRUE;
    } catch (...) {
        if (d.messenger) {
            auto destroy =
                reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(d.instance, "vkDestroyDebugUtilsMessengerEXT"));
            destroy(d.instance, d.messenger, nullptr);
        }
        vkDestroyInstance(d.instance, nullptr);
        throw;
    }
}

Device::Device(VkInstance instance, VkPhysicalDevice physicalDevice, VkDevice device, uint32_t queueFamily, VkQueue queue)
    : impl_(std::make_unique<Impl>()) {
    Impl& d = *impl_;
    d.instance = instance;
    d.physical = physicalDevice;
    d.device = device;
    d.queueFamily = queueFamily;
    d.queue = queue;
    d.info = describePhysicalDevice(physicalDevice, -1);
    if (d.info.apiVersion < VK_API_VERSION_1_2) throw ProbeError(fmt::format("Vulkan: {} is not a Vulkan 1.2 device", d.info.name));
    VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features12};
    vkGetPhysicalDeviceFeatures2(physicalDevice, &features);
    if (!features12.timelineSemaphore)
        throw ProbeError(fmt::format("Vulkan: {} has no timeline semaphores, which a Filter's Completion is", d.info.name));
    readProperties(d);
    d.imageCubeArray = features.features.imageCubeArray == VK_TRUE;
}

Device::~Device() {
    Impl& d = *impl_;
    d.retired.clear(); // the engine has idled the device before destroying this
    if (!d.owned) return;
    vkDestroyDevice(d.device, nullptr);
    if (d.messenger) {
        auto destroy =
            reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(d.instance, "vkDestroyDebugUtilsMessengerEXT"));
        destroy(d.instance, d.messenger, nullptr);
    }
    vkDestroyInstance(d.instance, nullptr);
}

const DeviceInfo& Device::info() const { return impl_->info; }

std::vector<std::string> Device::validationMessages() const {
    const std::lock_guard lock(impl_->messagesMutex);
    return impl_->messages;
}

VkInstance Device::instance() const { return impl_->instance; }
VkPhysicalDevice Device::physicalDevice() const { return impl_->physical; }
VkDevice Device::device() const { return impl_->device; }
uint32_t Device::queueFamily() const { return impl_->queueFamily; }
VkQueue Device::queue() const { return impl_->queue; }

} // namespace probe::gpu
