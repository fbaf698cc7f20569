// Device context: instance, validation with synchronization validation, device selection.
#include "device_access.hpp"
#include "device_memory_model.hpp"
#include "device_selection.hpp"
#include "vk_util.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <iterator>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <optional>
#include <string_view>

namespace skygraph::vk {

const char* resultName(VkResult r) noexcept {
    switch (r) {
#define SG_CASE(x) \
    case x:        \
        return #x;
        SG_CASE(VK_SUCCESS)
        SG_CASE(VK_NOT_READY)
        SG_CASE(VK_TIMEOUT)
        SG_CASE(VK_INCOMPLETE)
        SG_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        SG_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        SG_CASE(VK_ERROR_INITIALIZATION_FAILED)
        SG_CASE(VK_ERROR_DEVICE_LOST)
        SG_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        SG_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        SG_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        SG_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        SG_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        SG_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        SG_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        SG_CASE(VK_ERROR_SURFACE_LOST_KHR)
        SG_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
        SG_CASE(VK_SUBOPTIMAL_KHR)
        SG_CASE(VK_ERROR_OUT_OF_DATE_KHR)
#undef SG_CASE
        default:
            return "VkResult error";
    }
}

std::string extentText(VkExtent2D e) { return std::to_string(e.width) + "x" + std::to_string(e.height); }

std::string imageUsageText(VkImageUsageFlags usage) {
    static constexpr std::pair<VkImageUsageFlagBits, const char*> kNames[] = {
        {VK_IMAGE_USAGE_TRANSFER_SRC_BIT, "TRANSFER_SRC"},
        {VK_IMAGE_USAGE_TRANSFER_DST_BIT, "TRANSFER_DST"},
        {VK_IMAGE_USAGE_SAMPLED_BIT, "SAMPLED"},
        {VK_IMAGE_USAGE_STORAGE_BIT, "STORAGE"},
        {VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, "COLOR_ATTACHMENT"},
        {VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, "DEPTH_STENCIL_ATTACHMENT"},
        {VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT, "TRANSIENT_ATTACHMENT"},
        {VK_IMAGE_USAGE_INPUT_ATTACHMENT_BIT, "INPUT_ATTACHMENT"},
    };
    std::string text;
    for (const auto& [bit, name] : kNames)
        if (usage & bit) {
            text += text.empty() ? "" : " | ";
            text += name;
            usage &= ~VkImageUsageFlags(bit);
        }
    if (usage != 0) {
        char rest[16];
        std::snprintf(rest, sizeof rest, "0x%x", usage);
        text += (text.empty() ? "" : " | ") + std::string(rest);
    }
    return text.empty() ? "none" : text;
}

uint32_t findMemoryType(VkPhysicalDevice physical, uint32_t typeBits,
                        VkMemoryPropertyFlags required) {
    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(physical, &props);
    // Device-local memory that the host can also map (resizable BAR) is scarcer than plain
    // device-local memory: take it only when it is asked for or nothing else fits.
    const VkMemoryPropertyFlags avoided = required & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT
                                              ? 0u
                                              : VkMemoryPropertyFlags(VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    for (const VkMemoryPropertyFlags unwanted : {avoided, VkMemoryPropertyFlags(0)})
        for (uint32_t i = 0; i < props.memoryTypeCount; ++i) {
            const VkMemoryPropertyFlags flags = props.memoryTypes[i].propertyFlags;
            if ((typeBits & (1u << i)) && (flags & required) == required && (flags & unwanted) == 0) return i;
        }
    throw ExecutorError("no memory type with the required properties");
}

}  // namespace skygraph::vk

namespace skygraph {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr size_t kKeptMessages = 256;

VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT types,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data,
                                             void* user) {
    auto* impl = static_cast<DeviceAccess::Impl*>(user);
    const char* id = data->pMessageIdName ? data->pMessageIdName : "";
    const char* text = data->pMessage ? data->pMessage : "";
    // Performance advice (e.g. "use TRANSFER_SRC_OPTIMAL instead of GENERAL" for a pass that
    // both reads and writes by transfer) is counted apart: it is not a correctness problem,
    // but `skygraph check` reports it and can treat it as one.
    const bool performanceOnly = types == VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        std::lock_guard lock(impl->mutex);
        uint32_t& count = performanceOnly ? impl->performanceCount : impl->count;
        std::vector<ValidationMessage>& kept = performanceOnly ? impl->performanceKept : impl->kept;
        ++count;
        if (kept.size() < kKeptMessages) kept.push_back({severity, id, text});
    }
    if (impl->logMessages) {
        if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
            spdlog::error("[vulkan] {}", text);
        } else if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
            spdlog::warn("[vulkan] {}", text);
        } else {
            spdlog::debug("[vulkan] {}", text);
        }
    }
    return VK_FALSE;
}

/// The layer's specVersion, or 0 when it is not installed.
uint32_t layerVersion(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    for (const VkLayerProperties& l : layers)
        if (std::strcmp(l.layerName, name) == 0) return l.specVersion;
    return 0;
}

bool instanceExtensionAvailable(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateInstanceExtensionProperties(nullptr, &n, exts.data());
    return std::any_of(exts.begin(), exts.end(), [&](const VkExtensionProperties& e) {
        return std::strcmp(e.extensionName, name) == 0;
    });
}

bool deviceExtensionAvailable(VkPhysicalDevice pd, const char* name) {
    uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
    return std::any_of(exts.begin(), exts.end(), [&](const VkExtensionProperties& e) {
        return std::strcmp(e.extensionName, name) == 0;
    });
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

const char* typeName(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
        default: return "other";
    }
}

int typeRank(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
        default: return 4;
    }
}

/// What unsuitableReason (device_selection.hpp) needs to know of `pd`; with a `surface`,
/// whether each graphics+compute family presents to it.
detail::PhysicalDeviceFacts deviceFacts(VkPhysicalDevice pd, VkSurfaceKHR surface,
                                        const std::vector<std::string>& extensions) {
    detail::PhysicalDeviceFacts facts;
    for (const std::string& e : extensions)
        if (!deviceExtensionAvailable(pd, e.c_str())) {
            facts.missingExtension = e;
            break;
        }
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(pd, &props);
    facts.apiVersion = props.apiVersion;
    facts.pushDescriptor = deviceExtensionAvailable(pd, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);
    facts.swapchain = deviceExtensionAvailable(pd, VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    if (props.apiVersion >= VK_API_VERSION_1_3) {
        VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
        VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &f13};
        VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12, {}};
        vkGetPhysicalDeviceFeatures2(pd, &f2);
        facts.synchronization2 = f13.synchronization2 == VK_TRUE;
        facts.separateDepthStencilLayouts = f12.separateDepthStencilLayouts == VK_TRUE;
        facts.timelineSemaphore = f12.timelineSemaphore == VK_TRUE;
    }
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
    std::vector<VkQueueFamilyProperties> fams(n);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, fams.data());
    for (uint32_t i = 0; i < n; ++i) {
        const auto need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
        detail::QueueFamilyFacts f;
        f.graphicsAndCompute = (fams[i].queueFlags & need) == need;
        f.timestamps = fams[i].timestampValidBits != 0;
        f.compute = (fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT) != 0;
        const VkExtent3D g = fams[i].minImageTransferGranularity;
        f.transfers = (fams[i].queueFlags & (VK_QUEUE_TRANSFER_BIT | VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) != 0 &&
                      g.width == 1 && g.height == 1 && g.depth == 1;
        f.queueCount = fams[i].queueCount;
        if (surface && f.graphicsAndCompute && facts.swapchain) {
            VkBool32 presents = VK_FALSE;
            f.presents = vkGetPhysicalDeviceSurfaceSupportKHR(pd, i, surface, &presents) == VK_SUCCESS && presents;
        }
        facts.families.push_back(f);
    }
    return facts;
}

/// The presentation's instance extensions, each checked to be available.
std::vector<const char*> presentationExtensions(const PresentationOptions& presentation) {
    std::vector<const char*> names;
    for (const std::string& e : presentation.instanceExtensions) {
        if (!instanceExtensionAvailable(e.c_str()))
            throw ExecutorError("presenting needs the instance extension " + e + ", which this Vulkan installation lacks");
        names.push_back(e.c_str());
    }
    return names;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(instance, &n, nullptr);
    std::vector<VkPhysicalDevice> pds(n);
    vkEnumeratePhysicalDevices(instance, &n, pds.data());
    return pds;
}

/// Sets an environment variable for its lifetime, then puts back what was there (or nothing).
class ScopedEnvironment {
public:
    ScopedEnvironment(std::string name, const std::string& value) : name_(std::move(name)) {
        if (const char* previous = std::getenv(name_.c_str())) previous_ = previous;
        if (setenv(name_.c_str(), value.c_str(), 1) != 0) throw ExecutorError("cannot set " + name_);
    }
    ~ScopedEnvironment() {
        if (previous_) (void)setenv(name_.c_str(), previous_->c_str(), 1);
        else (void)unsetenv(name_.c_str());
    }
    ScopedEnvironment(const ScopedEnvironment&) = delete;
    ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

private:
    std::string name_;
    std::optional<std::string> previous_;
};

bool envFlag(const char* name) {
    const char* v = std::getenv(name);
    return v && *v && std::strcmp(v, "0") != 0 && lower(v) != "off" && lower(v) != "false";
}

/// Whether the variable is set to 0, off or false.
bool envFlagOff(const char* name) {
    const char* v = std::getenv(name);
    return v && *v && !envFlag(name);
}

/// Why vkCreateInstance failed, in words. The loader answers VK_ERROR_INCOMPATIBLE_DRIVER when
/// it finds no driver to load (none installed, or the driver variables name none), the usual
/// state of a fresh machine or container, which the result's name alone does not say.
std::string instanceCreationFailure(VkResult result) {
    std::string message = std::string("vkCreateInstance failed: ") + vk::resultName(result);
    if (result != VK_ERROR_INCOMPATIBLE_DRIVER) return message;
    message += ": no Vulkan driver was found";
    // The loader reads VK_DRIVER_FILES in place of VK_ICD_FILENAMES when both are set.
    for (const char* variable : {"VK_DRIVER_FILES", "VK_ICD_FILENAMES"})
        if (const char* files = std::getenv(variable); files && *files) {
            message += std::string(" (") + variable + " is set to '" + files + "', and no driver loads from it)";
            break;
        }
    return message + "; install one (Mesa's lavapipe runs on any CPU: apt install mesa-vulkan-drivers), or set "
                     "VK_ICD_FILENAMES to an installed driver's manifest, e.g. "
                     "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
}

}  // namespace

void Device::Impl::finish() {
    if (memoryModel) memoryModel->detach();
    if (device) {
        vkDeviceWaitIdle(device);
        vkDestroyDevice(device, nullptr);
        device = VK_NULL_HANDLE;
        queue = VK_NULL_HANDLE;
        queues = {};
    }
    if (surface) vkDestroySurfaceKHR(instance, surface, nullptr);
    surface = VK_NULL_HANDLE;
}

Device::Impl::~Impl() {
    finish();
    if (messenger) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance, messenger, nullptr);
    }
    if (instance) vkDestroyInstance(instance, nullptr);
}

namespace {
constexpr const char* kUserNames[] = {"Renderer", "Swapchain", "StagingBuffer", "SharedImage"};
static_assert(std::size(kUserNames) == kDeviceUserKinds, "a name per DeviceUser");
}  // namespace

std::string Device::Impl::liveUsers() const {
    std::vector<std::string> live;
    for (size_t u = 0; u < kDeviceUserKinds; ++u)
        if (const uint32_t n = users[u].load(); n > 0)
            live.push_back(std::to_string(n) + " " + kUserNames[u] + (n > 1 ? "s" : ""));
    std::string out;
    for (size_t i = 0; i < live.size(); ++i)
        out += (i == 0 ? "" : i + 1 == live.size() ? " and " : ", ") + live[i];
    return out;
}

detail::DeviceUse::DeviceUse(DeviceAccess::Impl& device, DeviceUser user) : device_(device), user_(user) {
    std::lock_guard lock(device_.usersMutex);
    if (device_.device == VK_NULL_HANDLE)
        throw ExecutorError(std::string("cannot make a ") + kUserNames[size_t(user)] +
                            " from a Device after Device::finish(): its device is destroyed");
    device_.users[size_t(user_)].fetch_add(1);
}
detail::DeviceUse::~DeviceUse() { device_.users[size_t(user_)].fetch_sub(1); }

Device::Device(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Device::~Device() {
    // What lives on would destroy its Vulkan objects with a destroyed device, which ends the
    // process inside the loader, far from the cause: say it here, where the order went wrong.
    if (const std::string live = impl_->liveUsers(); !live.empty()) {
        std::fprintf(stderr, "skygraph: Device destroyed while still alive, made from it: %s; destroy those before the Device\n",
                     live.c_str());
        std::abort();
    }
}

std::unique_ptr<Device> Device::create(const DeviceOptions& options) {
    auto impl = std::make_unique<Impl>();
    impl->logMessages = options.logMessages;
    impl->validation = options.validation || envFlag("SKYGRAPH_VALIDATION");
    if (impl->validation) {
        impl->layerVersion = layerVersion(kValidationLayer);
        if (impl->layerVersion == 0)
            throw ExecutorError("validation requested but VK_LAYER_KHRONOS_validation is not installed");
    }
    const bool debugUtils = instanceExtensionAvailable(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);

    // Layer 1.3.239 reads its QUEUE_SUBMIT synchronization checks only from its settings
    // (file or VK_LAYER_ENABLES); there is no API struct for it in this version. The
    // application's environment is its own again once the instance and device exist (on a
    // throw too).
    std::optional<ScopedEnvironment> layerEnables;
    if (impl->validation) {
        std::string enables = "VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT:"
                              "VALIDATION_CHECK_ENABLE_SYNCHRONIZATION_VALIDATION_QUEUE_SUBMIT";
        if (const char* prev = std::getenv("VK_LAYER_ENABLES"); prev && *prev) {
            if (std::strstr(prev, "QUEUE_SUBMIT") == nullptr) {
                enables = std::string(prev) + ":" + enables;
            } else {
                enables = prev;
            }
        }
        layerEnables.emplace("VK_LAYER_ENABLES", enables);
    }

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = options.applicationName.c_str();
    app.applicationVersion = options.applicationVersion;
    app.pEngineName = "skygraph";
    app.apiVersion = VK_API_VERSION_1_3;

    std::vector<const char*> layers;
    std::vector<const char*> exts;
    if (impl->validation) layers.push_back(kValidationLayer);
    if (debugUtils) exts.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (options.presentation) {
        for (const char* e : presentationExtensions(*options.presentation))
            if (std::none_of(exts.begin(), exts.end(), [&](const char* have) { return std::strcmp(have, e) == 0; }))
                exts.push_back(e);
    }

    VkValidationFeatureEnableEXT enables[] = {
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;

    VkDebugUtilsMessengerCreateInfoEXT messengerInfo{
        VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messengerInfo.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_INFO_BIT_EXT;
    messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messengerInfo.pfnUserCallback = debugCallback;
    messengerInfo.pUserData = impl.get();
    if (impl->validation) {
        features.pNext = debugUtils ? &messengerInfo : nullptr;
    }

    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pNext = impl->validation ? static_cast<const void*>(&features) : nullptr;
    ici.pApplicationInfo = &app;
    ici.enabledLayerCount = static_cast<uint32_t>(layers.size());
    ici.ppEnabledLayerNames = layers.data();
    ici.enabledExtensionCount = static_cast<uint32_t>(exts.size());
    ici.ppEnabledExtensionNames = exts.data();
    if (const VkResult created = vkCreateInstance(&ici, nullptr, &impl->instance); created != VK_SUCCESS)
        throw ExecutorError(instanceCreationFailure(created));

    if (debugUtils) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(impl->instance, "vkCreateDebugUtilsMessengerEXT"));
        if (create) {
            vk::check(create(impl->instance, &messengerInfo, nullptr, &impl->messenger),
                      "vkCreateDebugUtilsMessengerEXT");
        }
    }

    if (options.presentation) {
        if (!options.presentation->createSurface)
            throw ExecutorError("DeviceOptions::presentation has no createSurface");
        try {
            impl->surface = options.presentation->createSurface(impl->instance);
        } catch (const std::exception& e) {
            throw ExecutorError(std::string("creating the window's surface: ") + e.what());
        }
        if (!impl->surface) throw ExecutorError("DeviceOptions::presentation.createSurface returned no surface");
    }

    // Pick the physical device.
    const auto pds = physicalDevices(impl->instance);
    std::vector<detail::DeviceCandidate> candidates;
    VkPhysicalDevice chosen = VK_NULL_HANDLE;
    uint32_t chosenFamily = 0;
    const bool byIndex = !options.device.empty() &&
                         std::all_of(options.device.begin(), options.device.end(),
                                     [](unsigned char c) { return std::isdigit(c); });
    int bestRank = 1000;
    for (size_t i = 0; i < pds.size(); ++i) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(pds[i], &props);
        detail::DeviceCandidate& c = candidates.emplace_back();
        c.index = i;
        c.name = props.deviceName;
        c.type = typeName(props.deviceType);
        c.matched = options.device.empty() || (byIndex ? std::to_string(i) == options.device
                                                       : lower(c.name).find(lower(options.device)) != std::string::npos);
        if (!c.matched) continue;
        uint32_t family = 0;
        c.reason = detail::unsuitableReason(deviceFacts(pds[i], impl->surface, options.deviceExtensions),
                                            impl->surface != VK_NULL_HANDLE, family);
        if (!c.reason.empty()) continue;
        const int rank = typeRank(props.deviceType);
        if (rank < bestRank) {
            bestRank = rank;
            chosen = pds[i];
            chosenFamily = family;
        }
    }
    if (!chosen) throw ExecutorError(detail::noDeviceMessage(options.device, impl->surface != VK_NULL_HANDLE, candidates));
    impl->physical = chosen;
    impl->queueFamily = chosenFamily;
    const detail::PhysicalDeviceFacts chosenFacts = deviceFacts(chosen, impl->surface, options.deviceExtensions);
    const auto queueChoices = detail::chooseQueues(chosenFacts.families, chosenFamily,
                                                   options.separateQueues && !envFlagOff("SKYGRAPH_SEPARATE_QUEUES"));
    vkGetPhysicalDeviceProperties(chosen, &impl->properties);
    impl->name = impl->properties.deviceName;
    impl->timestampPeriod = impl->properties.limits.timestampPeriod;

    // Features: what passes need to really perform every access a usage can declare (stores
    // from vertex and fragment shaders, storage writes without a format, layered rendering).
    VkPhysicalDeviceFeatures supported;
    vkGetPhysicalDeviceFeatures(chosen, &supported);
    VkPhysicalDeviceVulkan12Features s12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 sf2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &s12, {}};
    vkGetPhysicalDeviceFeatures2(chosen, &sf2);

    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    f13.synchronization2 = VK_TRUE;
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    f12.pNext = &f13;
    f12.shaderOutputLayer = s12.shaderOutputLayer;
    // Both required: selection refused every device lacking them (unsuitableReason).
    f12.separateDepthStencilLayouts = VK_TRUE;
    f12.timelineSemaphore = VK_TRUE;
    f12.hostQueryReset = s12.hostQueryReset;
    impl->hostQueryReset = s12.hostQueryReset == VK_TRUE;
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12, {}};
    f2.features.robustBufferAccess = supported.robustBufferAccess;
    f2.features.vertexPipelineStoresAndAtomics = supported.vertexPipelineStoresAndAtomics;
    f2.features.fragmentStoresAndAtomics = supported.fragmentStoresAndAtomics;
    f2.features.shaderStorageImageWriteWithoutFormat =
        supported.shaderStorageImageWriteWithoutFormat;
    f2.features.geometryShader = supported.geometryShader;
    // A pass may blend one colour attachment (ReadWrite) and overwrite another.
    f2.features.independentBlend = supported.independentBlend;
    // A pass may combine its output with an integer attachment, which cannot blend.
    f2.features.logicOp = supported.logicOp;

    // One create info per family used, with as many queues as its highest chosen index needs.
    const std::array<float, kQueueKinds> priorities{1.0f, 1.0f, 1.0f};
    std::vector<VkDeviceQueueCreateInfo> queueInfos;
    for (const detail::QueueChoice& q : queueChoices) {
        auto it = std::find_if(queueInfos.begin(), queueInfos.end(),
                               [&](const VkDeviceQueueCreateInfo& c) { return c.queueFamilyIndex == q.family; });
        if (it == queueInfos.end()) {
            VkDeviceQueueCreateInfo& qci = queueInfos.emplace_back(VkDeviceQueueCreateInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO});
            qci.queueFamilyIndex = q.family;
            qci.pQueuePriorities = priorities.data();
            it = queueInfos.end() - 1;
        }
        it->queueCount = std::max(it->queueCount, q.index + 1);
    }
    std::vector<const char*> devExts{VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    if (impl->surface) devExts.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    for (const std::string& e : options.deviceExtensions)
        if (std::none_of(devExts.begin(), devExts.end(), [&](const char* have) { return e == have; }))
            devExts.push_back(e.c_str());
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.pNext = &f2;
    dci.queueCreateInfoCount = static_cast<uint32_t>(queueInfos.size());
    dci.pQueueCreateInfos = queueInfos.data();
    dci.enabledExtensionCount = static_cast<uint32_t>(devExts.size());
    dci.ppEnabledExtensionNames = devExts.data();
    vk::check(vkCreateDevice(chosen, &dci, nullptr, &impl->device), "vkCreateDevice");
    layerEnables.reset();
    for (size_t k = 0; k < kQueueKinds; ++k) {
        vkGetDeviceQueue(impl->device, queueChoices[k].family, queueChoices[k].index, &impl->queues[k]);
        impl->families[k] = queueChoices[k].family;
        impl->timestamps[k] = chosenFacts.families[queueChoices[k].family].timestamps;
    }
    impl->queue = impl->queues[static_cast<size_t>(QueueKind::Graphics)];
    impl->memoryModel = std::make_shared<detail::DeviceMemoryModel>(impl->device, chosen, impl->name, impl->families);

    impl->fn.cmdPushDescriptorSet = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
        vkGetDeviceProcAddr(impl->device, "vkCmdPushDescriptorSetKHR"));
    if (!impl->fn.cmdPushDescriptorSet) throw ExecutorError("vkCmdPushDescriptorSetKHR missing");
    if (debugUtils) {
        impl->fn.cmdBeginLabel = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
            vkGetInstanceProcAddr(impl->instance, "vkCmdBeginDebugUtilsLabelEXT"));
        impl->fn.cmdEndLabel = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
            vkGetInstanceProcAddr(impl->instance, "vkCmdEndDebugUtilsLabelEXT"));
        impl->fn.setObjectName = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
            vkGetInstanceProcAddr(impl->instance, "vkSetDebugUtilsObjectNameEXT"));
    }
    spdlog::info("skygraph: using device '{}'{}{}", impl->name,
                 impl->validation ? " with validation + synchronization validation" : "",
                 impl->surface ? ", presenting" : "");
    return std::unique_ptr<Device>(new Device(std::move(impl)));
}

std::vector<std::string> Device::listDevices() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_3;
    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    VkInstance instance = VK_NULL_HANDLE;
    std::vector<std::string> out;
    if (vkCreateInstance(&ici, nullptr, &instance) != VK_SUCCESS) return out;
    const auto pds = physicalDevices(instance);
    for (size_t i = 0; i < pds.size(); ++i) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(pds[i], &props);
        out.push_back(std::to_string(i) + ": " + props.deviceName + " (" +
                      typeName(props.deviceType) + ")");
    }
    vkDestroyInstance(instance, nullptr);
    return out;
}

VkInstance Device::instance() const noexcept { return impl_->instance; }
VkPhysicalDevice Device::physicalDevice() const noexcept { return impl_->physical; }
VkDevice Device::device() const noexcept { return impl_->device; }
VkQueue Device::queue() const noexcept { return impl_->queue; }
VkSurfaceKHR Device::surface() const noexcept { return impl_->surface; }
uint32_t Device::queueFamily() const noexcept { return impl_->queueFamily; }
VkQueue Device::queue(QueueKind kind) const noexcept { return impl_->queues[static_cast<size_t>(kind)]; }
std::array<uint32_t, kQueueKinds> Device::queueFamilies() const noexcept { return impl_->families; }
const std::string& Device::name() const noexcept { return impl_->name; }
bool Device::validationEnabled() const noexcept { return impl_->validation; }
float Device::timestampPeriodNs() const noexcept { return impl_->timestampPeriod; }
std::shared_ptr<const MemoryModel> Device::memoryModel() const noexcept { return impl_->memoryModel; }

uint64_t Device::allocatedBytes() const noexcept { return impl_->allocatedBytes.load(); }

uint32_t Device::messageCount() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->count;
}
std::vector<ValidationMessage> Device::messages() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->kept;
}
bool Device::hasMessage(std::string_view needle) const {
    std::lock_guard lock(impl_->mutex);
    return std::any_of(impl_->kept.begin(), impl_->kept.end(), [&](const ValidationMessage& m) {
        return m.idName.find(needle) != std::string::npos ||
               m.message.find(needle) != std::string::npos;
    });
}
void Device::finish() {
    std::lock_guard lock(impl_->usersMutex);
    if (const std::string live = impl_->liveUsers(); !live.empty())
        throw ExecutorError("Device::finish(): made from this device and still alive: " + live + "; destroy those first");
    impl_->finish();
}

uint32_t Device::performanceWarningCount() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->performanceCount;
}
std::vector<ValidationMessage> Device::performanceWarnings() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->performanceKept;
}

void Device::clearMessages() {
    std::lock_guard lock(impl_->mutex);
    impl_->count = 0;
    impl_->kept.clear();
    impl_->performanceCount = 0;
    impl_->performanceKept.clear();
}

}  // namespace skygraph
