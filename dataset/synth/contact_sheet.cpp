#include "dataset/synth/contact_sheet.h"

#include <algorithm>
#include <cmath>

#include "dataset/error.h"
#include "dataset/synth/random.h"
#include "dataset/synth/texture.h"

namespace pg::data::synth {

Image8 make_contact_sheet(const std::vector<Image8>& rgb, const std::vector<Image8>& masks, int columns, int gap) {
    std::vector<const Image8*> tiles;
    const size_t n = std::max(rgb.size(), masks.size());
    for (size_t i = 0; i < n; ++i) {
        if (i < rgb.size()) tiles.push_back(&rgb[i]);
        if (i < masks.size()) tiles.push_back(&masks[i]);
    }
    if (tiles.empty()) throw InputError("contact sheet", "no images");
    if (columns < 1) throw InputError("contact sheet", "needs at least one column");
    gap = std::max(0, gap);
    int cw = 0, ch = 0;
    for (const Image8* t : tiles) {
        if (t->channels != 3 || t->pixels.size() != size_t(t->width) * size_t(t->height) * 3)
            throw InputError("contact sheet", "tiles must be 8-bit RGB");
        cw = std::max(cw, t->width);
        ch = std::max(ch, t->height);
    }
    const int cols = std::min<int>(columns, int(tiles.size()));
    const int rows = int((tiles.size() + size_t(cols) - 1) / size_t(cols));
    Image8 sheet{gap + cols * (cw + gap), gap + rows * (ch + gap), 3, {}};
    sheet.pixels.assign(size_t(sheet.width) * size_t(sheet.height) * 3, 40);
    for (size_t k = 0; k < tiles.size(); ++k) {
        const Image8& t = *tiles[k];
        const int x0 = gap + int(k % size_t(cols)) * (cw + gap), y0 = gap + int(k / size_t(cols)) * (ch + gap);
        for (int y = 0; y < t.height; ++y)
            std::copy_n(t.pixels.begin() + long(size_t(y) * size_t(t.width) * 3), size_t(t.width) * 3,
                        sheet.pixels.begin() + long((size_t(y0 + y) * size_t(sheet.width) + size_t(x0)) * 3));
    }
    return sheet;
}

void write_contact_sheet(const std::filesystem::path& path, const Image8& sheet) {
    write_png8(path, sheet.width, sheet.height, sheet.channels, sheet.pixels);
}

}  // namespace pg::data::synth
