#include "engine/segment/export.h"

#include <cctype>
#include <set>

#include "dataset/cloud_select.h"
#include "dataset/error.h"
#include "dataset/formats/image_io.h"
#include "dataset/formats/scene_io.h"

namespace pg::seg {

namespace fs = std::filesystem;

std::string safe_file_name(std::string name) {
    for (char& c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
    return name.empty() || name == "." || name == ".." ? "object" : name;
}

void refuse_overwriting(const fs::path& file, const std::vector<fs::path>& inputs) {
    std::error_code ec;
    for (const auto& in : inputs)
        if (fs::exists(file) && fs::equivalent(file, in, ec))
            throw data::InputError(file.string(), "is an input of this run; choose another output folder");
}

void write_labelled_scene(const data::GaussianCloud& cloud, const std::vector<int32_t>& labels, const fs::path& file,
                          const std::string& property) {
    data::GaussianCloud labelled = cloud;
    labelled.set_int_property(property, labels);
    data::write_ply(labelled, file);
}

std::vector<fs::path> write_object_files(const data::GaussianCloud& cloud, const std::vector<int32_t>& labels,
                                         const std::vector<ExportObject>& objects, const fs::path& folder,
                                         const CloudWriter& write, const std::string& extension) {
    fs::create_directories(folder);
    std::multiset<std::string> names;
    for (auto& o : objects) names.insert(safe_file_name(o.name));
    std::vector<fs::path> paths;
    for (auto& o : objects) {
        std::string stem = safe_file_name(o.name);
        if (names.count(stem) > 1) stem += "_" + std::to_string(o.id);
        std::vector<uint32_t> idx;
        for (uint32_t i = 0; i < labels.size(); ++i)
            if (labels[i] == o.id) idx.push_back(i);
        paths.push_back(folder / (stem + extension));
        const data::GaussianCloud object = data::select_gaussians(cloud, idx);
        if (write) write(object, paths.back());
        else data::write_ply(object, paths.back());
    }
    return paths;
}

std::map<std::string, double> write_view_masks(vk::Context& ctx, const render::GpuScene& scene,
                                               const std::vector<int32_t>& labels,
                                               const std::vector<data::Camera>& cameras,
                                               const std::vector<size_t>& views, const fs::path& out,
                                               const ViewExportOptions& options, bool* completed) {
    if (completed) *completed = true;
    if (views.empty()) return {};
    MaskViews masker(ctx, scene, labels);
    fs::create_directories(out / "masks");
    fs::create_directories(out / "overlays");
    size_t done = 0;
    for (size_t v : views) {
        auto m = masker.render(cameras[v], options.masks);
        data::write_png16(out / "masks" / (cameras[v].name + ".png"), m.width, m.height, m.mask16());
        data::Image8 overlay{m.width, m.height, 3, m.overlay(options.colour)};
        data::report::draw_legend(overlay, options.legend);
        data::write_png8(out / "overlays" / (cameras[v].name + ".png"), m.width, m.height, 3, overlay.pixels);
        if (options.progress && !options.progress(++done, cameras[v].name)) {
            if (completed) *completed = false;
            break;
        }
    }
    return masker.stage_ms();
}

}  // namespace pg::seg
