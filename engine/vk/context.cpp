#include "engine/vk/context.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "engine/vk/check.h"
#include "engine/vk/pipeline.h"

namespace pg::vk {

namespace {

std::atomic<uint64_t> g_validation_messages{0};

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                     VkDebugUtilsMessageTypeFlagsEXT,
                                                     const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        g_validation_messages.fetch_add(1);
        std::fprintf(stderr, "vulkan validation: %s\n", data->pMessage);
    }
    return VK_FALSE;
}

bool env_flag(const char* name) {
    const char* v = std::getenv(name);
    return v && *v && std::strcmp(v, "0") != 0;
}

int type_rank(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
        default: return 4;
    }
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

bool has_extension(VkPhysicalDevice pd, const char* name) {
    uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
    for (auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

}  // namespace

std::string device_type_name(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
        default: return "other";
    }
}

uint64_t Context::validation_message_count() { return g_validation_messages.load(); }

Context::Context(const ContextOptions& options) : options_(options) {
    bool validation = options.validation || env_flag("PG_VALIDATION");
    options_.discrete_memory = options.discrete_memory || env_flag("PG_DISCRETE_MEMORY");
    if (const char* env = std::getenv("PG_FAULT_DEVICE_ALLOCATIONS"); env && options_.fail_allocations_after < 0)
        options_.fail_allocations_after = std::strtoll(env, nullptr, 10);
    if (const char* env = std::getenv("PG_FAULT_DEVICE_SUBMITS"); env && options_.fail_submits_after < 0)
        options_.fail_submits_after = std::strtoll(env, nullptr, 10);
    create_instance(validation);
    std::string wanted = options.device;
    if (wanted.empty())
        if (const char* env = std::getenv("PG_DEVICE")) wanted = env;
    pick_device(wanted);
    create_device();
    if (!options.quiet)
        std::fprintf(stderr, "device: %s (%s)%s%s\n", info_.name.c_str(), device_type_name(info_.type).c_str(),
                     validation ? ", validation on" : "", options_.discrete_memory ? ", discrete memory emulated" : "");
}

Context::~Context() {
    if (device_) vkDeviceWaitIdle(device_);
    attachments_.clear();
    pipelines_.clear();
    if (device_) vkDestroyDevice(device_, nullptr);
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance_, messenger_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
}

void Context::create_instance(bool validation) {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "PointGauss";
    app.apiVersion = VK_API_VERSION_1_2;

    std::vector<const char*> layers, extensions;
    for (auto& e : options_.instance_extensions) extensions.push_back(e.c_str());
    if (validation) {
        uint32_t n = 0;
        vkEnumerateInstanceLayerProperties(&n, nullptr);
        std::vector<VkLayerProperties> props(n);
        vkEnumerateInstanceLayerProperties(&n, props.data());
        bool found = std::any_of(props.begin(), props.end(),
                                 [](auto& p) { return std::strcmp(p.layerName, "VK_LAYER_KHRONOS_validation") == 0; });
        if (!found)
            throw std::runtime_error("validation requested but VK_LAYER_KHRONOS_validation is not installed "
                                     "(apt-get install vulkan-validationlayers)");
        layers.push_back("VK_LAYER_KHRONOS_validation");
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }
    VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ci.pApplicationInfo = &app;
    ci.enabledLayerCount = uint32_t(layers.size());
    ci.ppEnabledLayerNames = layers.data();
    ci.enabledExtensionCount = uint32_t(extensions.size());
    ci.ppEnabledExtensionNames = extensions.data();

    // Synchronization validation catches missing barriers, which plain validation cannot.
    VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;
    VkDebugUtilsMessengerCreateInfoEXT mci{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mci.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                      VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mci.pfnUserCallback = on_validation_message;
    if (validation) {
        mci.pNext = &features;
        ci.pNext = &mci;
    }
    VkResult r = vkCreateInstance(&ci, nullptr, &instance_);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw std::runtime_error("no Vulkan driver found (for a CPU device: apt-get install mesa-vulkan-drivers)");
    check(r, "vkCreateInstance");
    if (validation) {
        mci.pNext = nullptr;
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
        PG_VK(create(instance_, &mci, nullptr, &messenger_));
    }
}

std::vector<std::string> Context::list_devices() {
    ContextOptions o;
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ci.pApplicationInfo = &app;
    VkInstance inst;
    if (vkCreateInstance(&ci, nullptr, &inst) != VK_SUCCESS) return {};
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(inst, &n, nullptr);
    std::vector<VkPhysicalDevice> pds(n);
    vkEnumeratePhysicalDevices(inst, &n, pds.data());
    std::vector<std::string> names;
    for (auto pd : pds) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(pd, &p);
        names.push_back(std::string(p.deviceName) + " (" + device_type_name(p.deviceType) + ")");
    }
    vkDestroyInstance(inst, nullptr);
    return names;
}

void Context::pick_device(const std::string& wanted) {
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(instance_, &n, nullptr);
    std::vector<VkPhysicalDevice> pds(n);
    vkEnumeratePhysicalDevices(instance_, &n, pds.data());
    if (pds.empty()) throw std::runtime_error("no Vulkan device found (for a CPU device: apt-get install mesa-vulkan-drivers)");

    std::vector<std::pair<VkPhysicalDevice, VkPhysicalDeviceProperties>> usable;
    std::string names;
    for (auto pd : pds) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(pd, &p);
        names += std::string(names.empty() ? "" : ", ") + p.deviceName;
        if (p.apiVersion < VK_API_VERSION_1_2 || !has_extension(pd, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME)) continue;
        if (options_.can_present && (!has_extension(pd, VK_KHR_SWAPCHAIN_EXTENSION_NAME) || present_family(pd) < 0))
            continue;
        usable.push_back({pd, p});
    }
    if (!wanted.empty()) {
        auto it = std::find_if(usable.begin(), usable.end(), [&](auto& u) {
            return lower(u.second.deviceName).find(lower(wanted)) != std::string::npos;
        });
        if (it == usable.end())
            throw std::runtime_error("--device/PG_DEVICE '" + wanted + "' matches no usable device (have: " + names + ")");
        physical_ = it->first;
    } else {
        if (usable.empty())
            throw std::runtime_error(std::string("no device supports Vulkan 1.2 with VK_KHR_push_descriptor") +
                                     (options_.can_present ? " and presents to this window" : "") + " (have: " +
                                     names + ")");
        std::stable_sort(usable.begin(), usable.end(),
                         [](auto& a, auto& b) { return type_rank(a.second.deviceType) < type_rank(b.second.deviceType); });
        physical_ = usable.front().first;
    }

    VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceMaintenance4Properties m4{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_4_PROPERTIES};
    VkPhysicalDeviceMaintenance3Properties m3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    p2.pNext = &subgroup;
    subgroup.pNext = &m3;
    VkPhysicalDeviceProperties base;
    vkGetPhysicalDeviceProperties(physical_, &base);
    bool has_m4 = base.apiVersion >= VK_API_VERSION_1_3;
    if (has_m4) m3.pNext = &m4;
    vkGetPhysicalDeviceProperties2(physical_, &p2);
    const auto& lim = p2.properties.limits;
    info_.name = p2.properties.deviceName;
    info_.type = p2.properties.deviceType;
    info_.api_version = p2.properties.apiVersion;
    info_.max_storage_buffer_range = lim.maxStorageBufferRange;
    info_.max_texel_buffer_elements = lim.maxTexelBufferElements;
    info_.min_texel_buffer_offset_alignment = lim.minTexelBufferOffsetAlignment;
    info_.max_allocation_size = m3.maxMemoryAllocationSize;
    info_.max_buffer_size = has_m4 ? m4.maxBufferSize : m3.maxMemoryAllocationSize;
    for (int i = 0; i < 3; ++i) info_.max_group_count[i] = lim.maxComputeWorkGroupCount[i];
    info_.max_shared_memory = lim.maxComputeSharedMemorySize;
    info_.subgroup_size = subgroup.subgroupSize;
    info_.timestamp_period_ns = lim.timestampPeriod;

    vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
    info_.unified_memory = true;
    info_.device_memory_bytes = 0;
    for (uint32_t h = 0; h < memory_.memoryHeapCount; ++h)
        if (memory_.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            info_.device_memory_bytes += memory_.memoryHeaps[h].size;
    for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
        auto f = memory_.memoryTypes[i].propertyFlags;
        if ((f & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) && !(f & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)) info_.unified_memory = false;
    }
    if (options_.discrete_memory) info_.unified_memory = false;
}

void Context::create_device() {
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &n, nullptr);
    std::vector<VkQueueFamilyProperties> fams(n);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &n, fams.data());
    // Prefer a compute queue that also does graphics: it is the one with timestamps everywhere.
    int best = options_.can_present ? present_family(physical_) : -1;
    for (uint32_t i = 0; i < n && !options_.can_present; ++i) {
        if (!(fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
        if (best < 0 || (fams[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)) best = int(i);
        if (fams[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) break;
    }
    if (best < 0) throw std::runtime_error("device " + info_.name + " has no compute queue");
    queue_family_ = uint32_t(best);
    info_.timestamps = fams[best].timestampValidBits > 0;

    float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = queue_family_;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;

    VkPhysicalDeviceFeatures supported;
    vkGetPhysicalDeviceFeatures(physical_, &supported);
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.features.shaderInt64 = supported.shaderInt64;
    VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceVulkan12Features v12_supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    query.pNext = &v12_supported;
    vkGetPhysicalDeviceFeatures2(physical_, &query);
    v12.hostQueryReset = v12_supported.hostQueryReset;
    v12.shaderFloat16 = v12_supported.shaderFloat16;
    v12.storageBuffer8BitAccess = v12_supported.storageBuffer8BitAccess;
    v12.shaderInt8 = v12_supported.shaderInt8;
    features.pNext = &v12;

    std::vector<const char*> exts{VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    if (options_.can_present) exts.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.pNext = &features;
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.enabledExtensionCount = uint32_t(exts.size());
    dci.ppEnabledExtensionNames = exts.data();
    PG_VK(vkCreateDevice(physical_, &dci, nullptr, &device_));
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
    push_descriptor_fn =
        reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));
    if (!push_descriptor_fn) throw std::runtime_error("vkCmdPushDescriptorSetKHR missing on " + info_.name);
}

int Context::present_family(VkPhysicalDevice pd) const {
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
    std::vector<VkQueueFamilyProperties> fams(n);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, fams.data());
    const VkQueueFlags needed = VK_QUEUE_COMPUTE_BIT | VK_QUEUE_GRAPHICS_BIT;
    for (uint32_t i = 0; i < n; ++i)
        if ((fams[i].queueFlags & needed) == needed && options_.can_present(instance_, pd, i)) return int(i);
    return -1;
}

uint32_t Context::max_group_count_x() const {
    uint32_t limit = info_.max_group_count[0];
    if (options_.max_group_count_override) limit = std::min(limit, options_.max_group_count_override);
    return limit;
}

uint32_t Context::find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags required,
                                   VkMemoryPropertyFlags preferred) const {
    int fallback = -1;
    for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
        if (!(type_bits & (1u << i))) continue;
        auto f = memory_.memoryTypes[i].propertyFlags;
        if ((f & required) != required) continue;
        if ((f & preferred) == preferred) return i;
        if (fallback < 0) fallback = int(i);
    }
    if (fallback < 0) throw std::runtime_error("no suitable Vulkan memory type on " + info_.name);
    return uint32_t(fallback);
}

ComputePipeline& Context::pipeline(const std::string& shader, uint32_t buffer_count, uint32_t push_bytes) {
    std::lock_guard lock(pipelines_mutex_);
    auto& slot = pipelines_[shader];
    if (!slot) slot = std::make_unique<ComputePipeline>(*this, shader, buffer_count, push_bytes);
    return *slot;
}

std::vector<std::string> Context::pipeline_names() {
    std::lock_guard lock(pipelines_mutex_);
    std::vector<std::string> names;
    for (auto& [name, p] : pipelines_) names.push_back(name);
    return names;
}

const char* result_name(VkResult r) {
    switch (r) {
        case VK_SUCCESS: return "VK_SUCCESS";
        case VK_NOT_READY: return "VK_NOT_READY";
        case VK_TIMEOUT: return "VK_TIMEOUT";
        case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
        case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY (device memory is exhausted: --max-device-memory streams the scene in slabs, --half-sh halves its colours)";
        case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
        case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
        case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
        case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
        case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
        case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
        case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
        case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
        case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
        default: return "VkResult error";
    }
}

}  // namespace pg::vk
