#include "comparison_sheet.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bitmap_font.h"
#include "preview.h"

namespace probefilter {

namespace {

constexpr int kTextScale = 2;
constexpr int kPad = 6;
constexpr int kLabelBand = 7 * kTextScale + 2 * kPad;
constexpr std::array<std::uint8_t, 3> kWhite{255, 255, 255};

// Black -> purple -> red -> orange -> white, for t in [0, 1].
std::array<std::uint8_t, 3> heatColour(double t) {
    static constexpr double stops[5][3] = {{0, 0, 0}, {0.35, 0.0, 0.5}, {0.85, 0.1, 0.1}, {1.0, 0.6, 0.0}, {1.0, 1.0, 1.0}};
    t = std::isnan(t) ? 4.0 : std::clamp(t, 0.0, 1.0) * 4.0; // an undefined error shows as the largest
    const int k = std::min(static_cast<int>(t), 3);
    const double f = t - k;
    std::array<std::uint8_t, 3> c{};
    for (int i = 0; i < 3; ++i) c[i] = static_cast<std::uint8_t>(std::lround(255.0 * (stops[k][i] * (1.0 - f) + stops[k + 1][i] * f)));
    return c;
}

// Copies a panel of 8-bit RGB pixels into the sheet at (x, y).
void blit(std::vector<std::uint8_t>& sheet, int sheetWidth, const std::vector<std::uint8_t>& panel, int width, int height, int x, int y) {
    for (int row = 0; row < height; ++row)
        std::copy_n(&panel[static_cast<std::size_t>(row) * width * 3], width * 3,
                    &sheet[(static_cast<std::size_t>(y + row) * sheetWidth + x) * 3]);
}

} // namespace

std::vector<float> relativeError(const probe::Image& image, const probe::Image& reference) {
    std::vector<float> error(static_cast<std::size_t>(reference.width) * reference.height, 0.0f);
    for (std::size_t p = 0; p < error.size(); ++p) {
        double difference = 0.0, sum = 0.0;
        for (int c = 0; c < 3; ++c) {
            difference += std::abs(double(image.rgb[3 * p + c]) - reference.rgb[3 * p + c]);
            sum += std::abs(double(reference.rgb[3 * p + c]));
        }
        error[p] = sum > 0.0 ? static_cast<float>(difference / sum) : 0.0f;
    }
    return error;
}

double spheresL1(const probe::Image& image, const probe::Image& reference) {
    double difference = 0.0, sum = 0.0;
    for (std::size_t k = 0; k < reference.rgb.size(); ++k) {
        difference += std::abs(double(image.rgb[k]) - reference.rgb[k]);
        sum += std::abs(double(reference.rgb[k]));
    }
    return sum > 0.0 ? difference / sum : 0.0;
}

void writeComparisonSheet(const std::filesystem::path& png, const std::vector<SheetRow>& rows, float exposure, double maxError) {
    const probe::Image& reference = rows.front().spheres;
    const int panelWidth = reference.width, panelHeight = reference.height;
    const int width = 2 * panelWidth + kPad, rowHeight = kLabelBand + panelHeight;
    const int height = rowHeight * static_cast<int>(rows.size());
    std::vector<std::uint8_t> sheet(static_cast<std::size_t>(width) * height * 3, 24);

    for (std::size_t r = 0; r < rows.size(); ++r) {
        const int top = static_cast<int>(r) * rowHeight;
        drawText(sheet, width, height, kPad, top + kPad, rows[r].label, kTextScale, kWhite);
        blit(sheet, width, tonemap(rows[r].spheres, exposure), panelWidth, panelHeight, 0, top + kLabelBand);
        if (r == 0) continue;
        const std::vector<float> error = relativeError(rows[r].spheres, reference);
        std::vector<std::uint8_t> heat(error.size() * 3);
        for (std::size_t p = 0; p < error.size(); ++p) {
            const auto c = heatColour(error[p] / maxError);
            std::copy(c.begin(), c.end(), &heat[3 * p]);
        }
        blit(sheet, width, heat, panelWidth, panelHeight, panelWidth + kPad, top + kLabelBand);
        const std::string caption = fmt::format("ERROR: L1 {:.4f}", spheresL1(rows[r].spheres, reference));
        drawText(sheet, width, height, panelWidth + 2 * kPad, top + kPad, caption, kTextScale, kWhite);
    }

    // Legend, in the reference row's right half: the heat scale from 0 to maxError.
    const int barLeft = panelWidth + 3 * kPad, barWidth = panelWidth - 4 * kPad, barTop = kLabelBand + panelHeight / 2;
    const int barHeight = std::max(8, panelHeight / 8);
    for (int x = 0; x < barWidth; ++x) {
        const auto c = heatColour(double(x) / (barWidth - 1));
        for (int y = 0; y < barHeight; ++y)
            std::copy(c.begin(), c.end(), &sheet[(static_cast<std::size_t>(barTop + y) * width + barLeft + x) * 3]);
    }
    drawText(sheet, width, height, barLeft, barTop - kLabelBand + kPad, "RELATIVE ERROR PER PIXEL", kTextScale, kWhite);
    drawText(sheet, width, height, barLeft, barTop + barHeight + kPad, "0%", kTextScale, kWhite);
    const std::string top = fmt::format("{:.0f}%", 100.0 * maxError);
    drawText(sheet, width, height, barLeft + barWidth - textWidth(top, kTextScale), barTop + barHeight + kPad, top, kTextScale, kWhite);
    writePng(png, width, height, sheet);
}

} // namespace probefilter
