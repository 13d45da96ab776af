// --export-format: PLY through the dataset writer, SOG through it with the GPU clustering.
#include "app/cli/export_format.h"

#include "dataset/error.h"
#include "engine/compress/sog_quantizer.h"

namespace pg::app {

void add_export_format_option(CLI::App& cmd, std::string& format) {
    cmd.add_option("--export-format", format,
                   "3D outputs as ply (scene.ply with the labels, objects/NAME.ply) or sog (PlayCanvas SOG: "
                   "scene.sog without labels, objects/NAME.sog)")
        ->capture_default_str();
}

std::string scene_file_for(const std::string& format) {
    if (format == "ply") return "scene.ply";
    if (format == "sog") return "scene.sog";
    throw data::InputError("--export-format", "expected ply or sog, got '" + format + "'");
}

void write_3d_outputs(vk::Context& ctx, const std::string& format, const data::GaussianCloud& cloud,
                      const std::vector<int32_t>& labels, const std::string& property,
                      const std::vector<seg::ExportObject>& objects, const std::filesystem::path& stage,
                      const std::string& objects_folder) {
    if (scene_file_for(format) == "scene.ply") {
        seg::write_labelled_scene(cloud, labels, stage / "scene.ply", property);
        seg::write_object_files(cloud, labels, objects, stage / objects_folder);
        return;
    }
    const auto write_sog = compress::gpu_sog_writer(ctx);
    write_sog(cloud, stage / "scene.sog");
    seg::write_object_files(cloud, labels, objects, stage / objects_folder, write_sog, ".sog");
}

}  // namespace pg::app
