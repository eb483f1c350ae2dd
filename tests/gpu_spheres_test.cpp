// The sphere renderer: in a constant environment L, a white diffuse sphere is L everywhere (SH
// irradiance of a constant is the constant), a white metal sphere is L times the DFG albedo
// A + B (at most 1, 1 where it faces the camera and is smooth), and the background is L.
#include <cmath>

#include "gpu_test_support.h"
#include "probe/dfg.h"
#include "probe/error.h"
#include "probe/sh.h"
#include "probe/sheen.h"
#include "probe/synthetic.h"

using namespace probe;
using probetest::GpuTest;

class GpuSpheres : public GpuTest {};

TEST_F(GpuSpheres, ConstantEnvironment) {
    const float radiance = 3.0f;
    const CubeImage constant = constantProbe(16, glm::vec3(radiance));
    CubeLevels prefiltered;
    for (int m = 0; m < 4; ++m) prefiltered.push_back(constantProbe(16 >> m, glm::vec3(radiance)));
    const Image dfg = dfgTable(32, 256);

    gpu::SphereScene scene;
    scene.prefiltered = &prefiltered;
    scene.background = &constant;
    scene.irradiance = radianceToIrradiance(projectRadiance(constant));
    scene.dfg = &dfg;
    gpu::SphereMaterial chalk;
    chalk.baseColor = glm::vec3(1.0f);
    chalk.specular = 0.0f;
    chalk.hasSpecular = false;
    gpu::SphereMaterial mirror;
    mirror.baseColor = glm::vec3(1.0f);
    mirror.metallic = 1.0f;
    mirror.roughness = 0.0f;
    mirror.level = 0.0f;
    gpu::SphereMaterial rough = mirror;
    rough.roughness = 1.0f;
    rough.level = 3.0f;
    scene.materials = {chalk, mirror, rough};
    scene.cellSize = 32;
    const Image image = gpu::renderSpheres(probetest::testDevice(), scene);
    ASSERT_EQ(image.width, 96);
    ASSERT_EQ(image.height, 32);

    // Corners of every cell: background. Cell centres: the sphere facing the camera.
    for (int cell = 0; cell < 3; ++cell) EXPECT_FLOAT_EQ(image.pixel(32 * cell, 0).r, radiance);
    EXPECT_NEAR(image.pixel(16, 16).g, radiance, 1e-5 * radiance) << "white diffuse sphere";
    const glm::dvec2 smooth = dfgIntegral(1.0, 0.0, 1);
    EXPECT_NEAR(image.pixel(48, 16).r, radiance * (smooth.x + smooth.y), 2e-3 * radiance) << "smooth metal at normal incidence";
    const float roughCentre = image.pixel(80, 16).r;
    EXPECT_LT(roughCentre, 0.8f * radiance) << "a rough metal loses energy (single scattering)";
    EXPECT_GT(roughCentre, 0.2f * radiance);
    for (float v : image.rgb) EXPECT_LE(v, radiance * 1.001f);
}

// In a constant environment L the sheen layer gives sheenColor L S + (1 - max(sheenColor) E_s) times
// the layer below, at the sphere's centre (n.v = 1) S and E_s the sheen table's: a white diffuse
// sphere under a white sheen is L (S + 1 - E_s); black sheen is no sheen, pixel for pixel.
TEST_F(GpuSpheres, SheenLayerInAConstantEnvironment) {
    const float radiance = 2.0f;
    const CubeImage constant = constantProbe(16, glm::vec3(radiance));
    CubeLevels prefiltered;
    for (int m = 0; m < 4; ++m) prefiltered.push_back(constantProbe(16 >> m, glm::vec3(radiance)));
    const Image dfg = dfgTable(32, 256), sheen = sheenTable(32, 1024);
    gpu::SphereScene scene;
    scene.prefiltered = &prefiltered;
    scene.background = &constant;
    scene.irradiance = radianceToIrradiance(projectRadiance(constant));
    scene.dfg = &dfg;
    scene.sheen = &prefiltered;
    scene.sheenTable = &sheen;
    gpu::SphereMaterial chalk;
    chalk.baseColor = glm::vec3(1.0f);
    chalk.specular = 0.0f;
    chalk.hasSpecular = false;
    gpu::SphereMaterial velvet = chalk;
    velvet.sheenColor = glm::vec3(1.0f);
    velvet.sheenRoughness = 0.9f;
    velvet.sheenLevel = 2.7f;
    scene.materials = {chalk, velvet};
    scene.cellSize = 32;
    const Image image = gpu::renderSpheres(probetest::testDevice(), scene);

    // The centre pixel faces the camera to within a pixel: the table's last column (n.v = 1 - 1/64),
    // bilinear between rows 28 and 29 at roughness 0.9.
    const glm::vec3 a = sheen.pixel(31, 28), b = sheen.pixel(31, 29);
    const float f = 0.9f * 32.0f - 0.5f - 28.0f;
    const glm::vec3 se = a + (b - a) * f;
    EXPECT_NEAR(image.pixel(16, 16).r, radiance, 1e-5 * radiance) << "no sheen";
    EXPECT_NEAR(image.pixel(48, 16).r, radiance * (se.r + 1.0f - se.g), 2e-2 * radiance) << "white sheen over white chalk";
    EXPECT_GT(se.r, 0.05f) << "the test sees the sheen term";

    // Black sheen: the material without sheen, and the scene needs neither the levels nor the table.
    gpu::SphereScene plain = scene;
    plain.sheen = nullptr;
    plain.sheenTable = nullptr;
    gpu::SphereMaterial black = velvet;
    black.sheenColor = glm::vec3(0.0f);
    plain.materials = {chalk, black};
    const Image without = gpu::renderSpheres(probetest::testDevice(), plain);
    for (int x = 32; x < 64; ++x)
        for (int y = 0; y < 32; ++y) ASSERT_EQ(without.pixel(x, y), image.pixel(x - 32, y)) << x << "," << y;
    // Sheen without its levels is refused.
    plain.materials = {velvet};
    EXPECT_THROW(gpu::renderSpheres(probetest::testDevice(), plain), ProbeError);
}

// The background is read bilinearly: where a cell's pixels are smaller than a texel of a checkerboard
// background, it shows values between the squares' two, not blocks of one or the other.
TEST_F(GpuSpheres, BackgroundIsInterpolated) {
    const CubeImage checker = checkerProbe(8);
    CubeLevels prefiltered{checker};
    gpu::SphereScene scene;
    scene.prefiltered = &prefiltered;
    scene.background = &checker;
    gpu::SphereMaterial chalk;
    chalk.specular = 0.0f;
    chalk.hasSpecular = false;
    scene.materials = {chalk};
    scene.cellSize = 64;
    const Image image = gpu::renderSpheres(probetest::testDevice(), scene);
    int between = 0, pixels = 0;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < image.width; ++x, ++pixels) {
            const float v = image.pixel(x, y).g;
            if (v > 0.06f && v < 0.99f) ++between;
        }
    EXPECT_GT(between, pixels / 2) << "the background shows the checkerboard's texels as blocks";
}

// A scene's every material is drawn: spheres past what one storage buffer of the guaranteed range
// holds (227 of 192^2) are drawn in further batches, each cell as it is drawn alone. A batch is
// 8.4M pixels, a dispatch of more than 65535 workgroups.
TEST_F(GpuSpheres, ManyMaterialsInBatches) {
    const CubeImage sky = syntheticProbe("sky", 16);
    CubeLevels prefiltered;
    for (int m = 0; m < 4; ++m) prefiltered.push_back(syntheticProbe("sky", 16 >> m));
    const Image dfg = dfgTable(32, 256);
    gpu::SphereScene scene;
    scene.prefiltered = &prefiltered;
    scene.background = &sky;
    scene.irradiance = radianceToIrradiance(projectRadiance(sky));
    scene.dfg = &dfg;
    scene.cellSize = 192;
    for (int k = 0; k < 230; ++k) {
        gpu::SphereMaterial m;
        m.baseColor = glm::vec3(0.2f + 0.003f * static_cast<float>(k), 0.5f, 0.7f);
        m.metallic = static_cast<float>(k % 2);
        m.roughness = static_cast<float>(k % 4) / 3.0f;
        m.level = 3.0f * m.roughness;
        scene.materials.push_back(m);
    }
    const Image all = gpu::renderSpheres(probetest::testDevice(), scene);
    ASSERT_EQ(all.width, 230 * 192);

    const std::vector<gpu::SphereMaterial> materials = scene.materials;
    for (int k : {0, 226, 227, 229}) {
        scene.materials = {materials[static_cast<std::size_t>(k)]};
        const Image alone = gpu::renderSpheres(probetest::testDevice(), scene);
        int differing = 0;
        for (int y = 0; y < 192; ++y)
            for (int x = 0; x < 192; ++x)
                if (alone.pixel(x, y) != all.pixel(192 * k + x, y)) ++differing;
        EXPECT_EQ(differing, 0) << "material " << k;
    }
}
