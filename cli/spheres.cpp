#include "spheres.h"

#include "preview.h"

namespace probefilter {

probe::gpu::SphereMaterial sphereMaterial(const probe::SceneMaterial& material, const probe::RoughnessMapping& mapping, int levelCount) {
    probe::gpu::SphereMaterial m;
    m.baseColor = glm::vec3(material.baseColor);
    m.metallic = static_cast<float>(material.metallic);
    m.specular = static_cast<float>(material.specular);
    m.roughness = static_cast<float>(material.roughness);
    m.level = static_cast<float>(probe::roughnessToLevel(mapping, material.roughness, levelCount));
    m.hasSpecular = material.hasSpecular();
    m.sheenColor = glm::vec3(material.sheenColor);
    m.sheenRoughness = static_cast<float>(material.sheenRoughness);
    m.sheenLevel = static_cast<float>(probe::roughnessToLevel(mapping, material.sheenRoughness, levelCount));
    return m;
}

probe::Image writeSpheres(const std::filesystem::path& png, const probe::gpu::Device& device, const probe::gpu::SphereScene& scene) {
    probe::Image image = probe::gpu::renderSpheres(device, scene);
    writePng(png, image.width, image.height, tonemap(image, autoExposure(*scene.background)));
    return image;
}

} // namespace probefilter
