// A small line plotter on an RGB float canvas (written with msmcl's PNG writer), with a
// 5x7 bitmap font for titles, ticks and the legend.
#include "plot.hpp"

#include "io/png_io.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>

namespace msmcl::bench {

namespace {

struct Color {
    float r, g, b;
};

// 5x7 glyphs, one row per byte, bit 4 = leftmost column.
const std::map<char, std::array<std::uint8_t, 7>>& font() {
    static const std::map<char, std::array<std::uint8_t, 7>> glyphs = {
        {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}}, {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
        {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}}, {'D', {0x1E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1E}},
        {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}}, {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
        {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}}, {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
        {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}}, {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
        {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}}, {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
        {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}}, {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
        {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
        {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}}, {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
        {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}}, {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
        {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
        {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}}, {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
        {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}}, {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
        {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
        {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
        {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
        {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
        {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
        {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}}, {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}},
        {'=', {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}}, {'^', {0x04, 0x0A, 0x11, 0x00, 0x00, 0x00, 0x00}},
        {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}}, {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
        {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}}, {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
        {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}}, {',', {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}},
    };
    return glyphs;
}

class Canvas {
public:
    Canvas(int width, int height) : width_(width), height_(height), rgb_(std::size_t(width) * height * 3, 1.0f) {}

    void pixel(int x, int y, Color c) {
        if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
        float* p = &rgb_[(std::size_t(y) * width_ + x) * 3];
        p[0] = c.r, p[1] = c.g, p[2] = c.b;
    }
    void rect(int x0, int y0, int x1, int y1, Color c) {
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) pixel(x, y, c);
    }
    // A line `thickness` pixels wide (squares along a DDA).
    void line(double x0, double y0, double x1, double y1, Color c, int thickness = 1) {
        const int steps = std::max(1, int(std::ceil(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0)))));
        for (int i = 0; i <= steps; ++i) {
            const double t = double(i) / steps;
            const int x = int(std::lround(x0 + t * (x1 - x0))), y = int(std::lround(y0 + t * (y1 - y0)));
            rect(x - thickness / 2, y - thickness / 2, x + (thickness - 1) / 2, y + (thickness - 1) / 2, c);
        }
    }
    // Upper-case text at scale `scale` (6 x 8 pixels per character cell at scale 1).
    void text(int x, int y, const std::string& s, Color c, int scale = 2) {
        for (char raw : s) {
            const char ch = static_cast<char>(std::toupper(static_cast<unsigned char>(raw)));
            const auto glyph = font().find(ch);
            if (glyph != font().end())
                for (int row = 0; row < 7; ++row)
                    for (int col = 0; col < 5; ++col)
                        if (glyph->second[row] >> (4 - col) & 1)
                            rect(x + col * scale, y + row * scale, x + col * scale + scale - 1,
                                 y + row * scale + scale - 1, c);
            x += 6 * scale;
        }
    }
    static int text_width(const std::string& s, int scale = 2) { return int(s.size()) * 6 * scale; }

    void save(const std::string& path) const { io::write_png_preview(path, width_, height_, 3, rgb_); }

private:
    int width_, height_;
    std::vector<float> rgb_;
};

Color case_color(const std::string& name, int index) {
    static const std::map<std::string, Color> known = {
        {"fused", {0.85f, 0.1f, 0.1f}},      {"fused_paper", {0.95f, 0.55f, 0.0f}}, {"three_pass", {0.1f, 0.3f, 0.9f}},
        {"cpu_loop", {0.1f, 0.6f, 0.2f}},    {"opencv", {0.55f, 0.2f, 0.7f}},      {"copy", {0.45f, 0.45f, 0.45f}},
        {"first_call", {0.0f, 0.0f, 0.0f}},
    };
    if (auto found = known.find(name); found != known.end()) return found->second;
    const float hue = 0.13f * index;
    return {0.5f + 0.4f * std::sin(6.28f * hue), 0.5f + 0.4f * std::sin(6.28f * hue + 2.1f),
            0.5f + 0.4f * std::sin(6.28f * hue + 4.2f)};
}

std::string format_ms(double ms) {
    char text[32];
    if (ms >= 1.0) std::snprintf(text, sizeof text, "%g", ms);
    else std::snprintf(text, sizeof text, "%.2g", ms);
    return text;
}

} // namespace

void write_cost_plot(const std::string& path, const std::vector<nlohmann::json>& rows) {
    // Panels: formats (rows) x sample counts (columns); series: cases with throughput.
    std::vector<std::string> formats, cases;
    std::set<int> sample_set, size_set;
    double lowest = 1e30, highest = 0.0;
    for (const nlohmann::json& row : rows) {
        if (row["mtexels_per_s"].is_null()) continue;
        const std::string format = row["format"], name = row["case"];
        if (std::find(formats.begin(), formats.end(), format) == formats.end()) formats.push_back(format);
        if (std::find(cases.begin(), cases.end(), name) == cases.end()) cases.push_back(name);
        sample_set.insert(row["samples"].get<int>());
        size_set.insert(row["size"].get<int>());
        lowest = std::min(lowest, row["ms_median"].get<double>());
        highest = std::max(highest, row["ms_median"].get<double>());
    }
    const std::vector<int> sample_counts(sample_set.begin(), sample_set.end());
    const std::vector<int> sizes(size_set.begin(), size_set.end());
    const int panel_w = 520, panel_h = 360, legend_entry_w = 240;
    const int columns = std::max<int>(1, int(sample_counts.size())), panel_rows = std::max<int>(1, int(formats.size()));
    const int legend_columns = std::max(1, (columns * panel_w - 80) / legend_entry_w);
    const int legend_h = 40 + 26 * int((cases.size() + legend_columns - 1) / legend_columns);
    Canvas canvas(columns * panel_w, panel_rows * panel_h + legend_h);
    const Color ink{0, 0, 0}, grid{0.85f, 0.85f, 0.85f};
    if (cases.empty()) {
        canvas.text(20, 20, "NO ROWS", ink);
        canvas.save(path);
        return;
    }
    // Shared axes: decades of ms, sizes on a log2 scale.
    const double y_low = std::pow(10.0, std::floor(std::log10(lowest))),
                 y_high = std::pow(10.0, std::ceil(std::log10(highest * 1.0001)));
    const double x_low = std::log2(double(sizes.front())), x_high = std::log2(double(sizes.back()));
    for (int pr = 0; pr < panel_rows; ++pr) {
        for (int pc = 0; pc < columns; ++pc) {
            const int left = pc * panel_w + 80, right = pc * panel_w + panel_w - 20;
            const int top = pr * panel_h + 40, bottom = pr * panel_h + panel_h - 50;
            const auto px = [&](int size) {
                if (x_high == x_low) return 0.5 * (left + right);
                return left + 20 + (std::log2(double(size)) - x_low) / (x_high - x_low) * (right - left - 40);
            };
            const auto py = [&](double ms) {
                return bottom - (std::log10(ms) - std::log10(y_low)) / (std::log10(y_high) - std::log10(y_low)) *
                                    (bottom - top);
            };
            canvas.text(left, top - 30, formats[pr] + "  S=" + std::to_string(sample_counts[pc]) + "  MS (MEDIAN)", ink);
            // Decade grid and labels, size ticks.
            for (double ms = y_low; ms <= y_high * 1.0001; ms *= 10.0) {
                const double y = py(ms);
                canvas.line(left, y, right, y, grid);
                canvas.text(left - 12 - Canvas::text_width(format_ms(ms)), int(y) - 7, format_ms(ms), ink);
            }
            for (int size : sizes) {
                const double x = px(size);
                canvas.line(x, top, x, bottom, grid);
                const std::string label = std::to_string(size) + "^2";
                canvas.text(int(x) - Canvas::text_width(label) / 2, bottom + 10, label, ink);
            }
            canvas.line(left, top, left, bottom, ink);
            canvas.line(left, bottom, right, bottom, ink);
            // One polyline per case.
            for (std::size_t k = 0; k < cases.size(); ++k) {
                std::vector<std::pair<double, double>> points;
                for (int size : sizes)
                    for (const nlohmann::json& row : rows)
                        if (row["case"] == cases[k] && row["format"] == formats[pr] &&
                            row["samples"] == sample_counts[pc] && row["size"] == size &&
                            !row["mtexels_per_s"].is_null())
                            points.emplace_back(px(size), py(row["ms_median"].get<double>()));
                const Color color = case_color(cases[k], int(k));
                for (std::size_t i = 0; i < points.size(); ++i) {
                    canvas.rect(int(points[i].first) - 3, int(points[i].second) - 3, int(points[i].first) + 3,
                                int(points[i].second) + 3, color);
                    if (i > 0)
                        canvas.line(points[i - 1].first, points[i - 1].second, points[i].first, points[i].second,
                                    color, 3);
                }
            }
        }
    }
    // Legend under the panels.
    const int legend_top = panel_rows * panel_h + 10;
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const int x = 80 + int(k % legend_columns) * legend_entry_w, y = legend_top + 26 * int(k / legend_columns);
        canvas.rect(x, y + 4, x + 30, y + 8, case_color(cases[k], int(k)));
        canvas.text(x + 40, y, cases[k], ink);
    }
    canvas.save(path);
}

} // namespace msmcl::bench
