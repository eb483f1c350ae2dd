// Writes the bad inputs that cli_bad_input.sh feeds to the command line.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include "probe/probe_io.h"
#include "probe/synthetic.h"

using namespace probe;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: make_bad_probes DIR\n");
        return 2;
    }
    const fs::path dir = argv[1];
    fs::create_directories(dir);
    const Image good = cubeToStrip(skyProbe(8));
    writeExr(dir / "good.exr", good);

    auto withPixel = [&](const char* name, float value) {
        Image image = good;
        image.rgb[(3 * image.width + 17) * 3 + 1] = value;
        writeExr(dir / name, image);
    };
    withPixel("nan.exr", std::numeric_limits<float>::quiet_NaN());
    withPixel("inf.exr", std::numeric_limits<float>::infinity());
    withPixel("negative.exr", -2.0f);
    writeExr(dir / "aspect.exr", Image{30, 20, std::vector<float>(30 * 20 * 3, 1.0f)});
    std::ofstream(dir / "empty.exr").close();
    std::ofstream(dir / "garbage.exr") << "this is not an image at all, just text pretending to be one\n";

    // A real EXR cut in half: the header parses, the pixels do not.
    const auto size = fs::file_size(dir / "good.exr");
    std::ifstream in(dir / "good.exr", std::ios::binary);
    std::vector<char> bytes(size);
    in.read(bytes.data(), static_cast<std::streamsize>(size));
    std::ofstream(dir / "truncated.exr", std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(size / 2));
    return 0;
}
