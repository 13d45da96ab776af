// COLMAP sparse model writer (text and binary): one COLMAP camera per image, image ids and
// camera ids 1..N in the given order, image names "<name>.png", and an empty points3D file
// so COLMAP tools open the model.
#include <bit>
#include <cmath>
#include <cstdint>
#include <ostream>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/camera_import.h"
#include "dataset/formats/camera_io.h"

namespace pg::data {

namespace fs = std::filesystem;

namespace detail {

glm::dvec4 qvec_from_rotation(const glm::dmat3& R) {
    auto m = [&](int row, int col) { return R[col][row]; };
    const double trace = m(0, 0) + m(1, 1) + m(2, 2);
    glm::dvec4 q;  // (w, x, y, z)
    if (trace > 0) {
        const double s = 2 * std::sqrt(trace + 1);
        q = {s / 4, (m(2, 1) - m(1, 2)) / s, (m(0, 2) - m(2, 0)) / s, (m(1, 0) - m(0, 1)) / s};
    } else if (m(0, 0) > m(1, 1) && m(0, 0) > m(2, 2)) {
        const double s = 2 * std::sqrt(1 + m(0, 0) - m(1, 1) - m(2, 2));
        q = {(m(2, 1) - m(1, 2)) / s, s / 4, (m(0, 1) + m(1, 0)) / s, (m(0, 2) + m(2, 0)) / s};
    } else if (m(1, 1) > m(2, 2)) {
        const double s = 2 * std::sqrt(1 + m(1, 1) - m(0, 0) - m(2, 2));
        q = {(m(0, 2) - m(2, 0)) / s, (m(0, 1) + m(1, 0)) / s, s / 4, (m(1, 2) + m(2, 1)) / s};
    } else {
        const double s = 2 * std::sqrt(1 + m(2, 2) - m(0, 0) - m(1, 1));
        q = {(m(1, 0) - m(0, 1)) / s, (m(0, 2) + m(2, 0)) / s, (m(1, 2) + m(2, 1)) / s, s / 4};
    }
    q = glm::normalize(q);
    return q[0] < 0 ? -q : q;
}

}  // namespace detail

namespace {

static_assert(std::endian::native == std::endian::little, "COLMAP binary files are little-endian");

struct ColmapParams {
    const detail::ColmapModel* model;
    std::vector<double> params;
};

const detail::ColmapModel& model(int id) { return detail::colmap_models[size_t(id)]; }

// The camera's own model when COLMAP can hold it exactly, else PINHOLE (no distortion) or
// the equivalent OPENCV (radial models pad to k1 k2 p1 p2).
ColmapParams colmap_params(const Camera& c, const fs::path& file) {
    const auto& d = c.distortion;
    const bool one_focal = c.fx == c.fy;
    if (c.model == "SIMPLE_PINHOLE" && one_focal && !c.has_distortion()) return {&model(0), {c.fx, c.cx, c.cy}};
    if (c.model == "SIMPLE_RADIAL" && one_focal && d.size() == 1) return {&model(2), {c.fx, c.cx, c.cy, d[0]}};
    if (c.model == "RADIAL" && one_focal && d.size() == 2) return {&model(3), {c.fx, c.cx, c.cy, d[0], d[1]}};
    if (c.model == "OPENCV" && d.size() == 4) return {&model(4), {c.fx, c.fy, c.cx, c.cy, d[0], d[1], d[2], d[3]}};
    if (!c.has_distortion()) return {&model(1), {c.fx, c.fy, c.cx, c.cy}};
    const bool radial = (c.model == "SIMPLE_RADIAL" && d.size() == 1) || (c.model == "RADIAL" && d.size() == 2) ||
                        (c.model == "OPENCV" && d.size() <= 4);
    if (!radial)
        throw InputError(file.string(), "camera '" + c.name + "': cannot write " + c.model + " distortion with " +
                                            std::to_string(d.size()) + " coefficients to COLMAP");
    std::vector<double> p = {c.fx, c.fy, c.cx, c.cy, 0, 0, 0, 0};
    for (size_t k = 0; k < d.size(); ++k) p[4 + k] = d[k];
    return {&model(4), p};
}

void check_for_writing(const std::vector<Camera>& cams, const fs::path& file) {
    for (const Camera& c : cams) {
        detail::check_camera(c, file);
        if (c.name.find_first_of(std::string("\n\r\0", 3)) != std::string::npos)
            throw InputError(file.string(), "camera '" + c.name + "': name contains a line break or NUL");
    }
}

void make_folder(const fs::path& dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw InputError(dir.string(), "cannot create folder: " + ec.message());
}

std::string image_file_name(const Camera& c) { return c.name + ".png"; }

template <class T>
void put(std::ostream& out, T v) {
    out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

}  // namespace

void write_colmap_text(const std::vector<Camera>& cams, const fs::path& model_dir) {
    check_for_writing(cams, model_dir / "cameras.txt");
    std::vector<ColmapParams> params;
    for (const Camera& c : cams) params.push_back(colmap_params(c, model_dir / "cameras.txt"));
    make_folder(model_dir);

    write_atomically(model_dir / "cameras.txt", [&](std::ostream& out) {
        out.precision(17);
        out << "# Camera list with one line of data per camera:\n"
               "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
               "# Number of cameras: "
            << cams.size() << "\n";
        for (size_t i = 0; i < cams.size(); ++i) {
            out << i + 1 << ' ' << params[i].model->name << ' ' << cams[i].width << ' ' << cams[i].height;
            for (double p : params[i].params) out << ' ' << p;
            out << '\n';
        }
    });
    write_atomically(model_dir / "images.txt", [&](std::ostream& out) {
        out.precision(17);
        out << "# Image list with two lines of data per image:\n"
               "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
               "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
               "# Number of images: "
            << cams.size() << ", mean observations per image: 0\n";
        for (size_t i = 0; i < cams.size(); ++i) {
            const glm::dvec4 q = detail::qvec_from_rotation(cams[i].R);
            const glm::dvec3& t = cams[i].t;
            out << i + 1 << ' ' << q[0] << ' ' << q[1] << ' ' << q[2] << ' ' << q[3] << ' ' << t.x << ' ' << t.y << ' '
                << t.z << ' ' << i + 1 << ' ' << image_file_name(cams[i]) << "\n\n";
        }
    });
    write_atomically(model_dir / "points3D.txt", [&](std::ostream& out) {
        out << "# 3D point list with one line of data per point:\n"
               "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
               "# Number of points: 0, mean track length: 0\n";
    });
}

void write_colmap_binary(const std::vector<Camera>& cams, const fs::path& model_dir) {
    check_for_writing(cams, model_dir / "cameras.bin");
    std::vector<ColmapParams> params;
    for (const Camera& c : cams) params.push_back(colmap_params(c, model_dir / "cameras.bin"));
    make_folder(model_dir);

    write_atomically(model_dir / "cameras.bin", [&](std::ostream& out) {
        put<uint64_t>(out, cams.size());
        for (size_t i = 0; i < cams.size(); ++i) {
            put<int32_t>(out, int32_t(i + 1));
            put<int32_t>(out, params[i].model->id);
            put<uint64_t>(out, uint64_t(cams[i].width));
            put<uint64_t>(out, uint64_t(cams[i].height));
            for (double p : params[i].params) put<double>(out, p);
        }
    });
    write_atomically(model_dir / "images.bin", [&](std::ostream& out) {
        put<uint64_t>(out, cams.size());
        for (size_t i = 0; i < cams.size(); ++i) {
            put<int32_t>(out, int32_t(i + 1));
            const glm::dvec4 q = detail::qvec_from_rotation(cams[i].R);
            for (int k = 0; k < 4; ++k) put<double>(out, q[k]);
            for (int k = 0; k < 3; ++k) put<double>(out, cams[i].t[k]);
            put<int32_t>(out, int32_t(i + 1));
            const std::string name = image_file_name(cams[i]);
            out.write(name.c_str(), std::streamsize(name.size() + 1));  // with its NUL
            put<uint64_t>(out, 0);                                         // no 2D points
        }
    });
    write_atomically(model_dir / "points3D.bin", [&](std::ostream& out) { put<uint64_t>(out, 0); });
}

}  // namespace pg::data
