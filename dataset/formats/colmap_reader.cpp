// COLMAP sparse model reader: cameras and images, .bin (preferred) or .txt. Image poses are
// already world-to-camera in the OpenCV convention; points3D is not read.
#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string_view>

#include "dataset/atomic_file.h"
#include "dataset/error.h"
#include "dataset/formats/camera_import.h"
#include "dataset/formats/camera_io.h"

namespace pg::data {

namespace fs = std::filesystem;

namespace detail {

glm::dmat3 rotation_from_qvec(const glm::dvec4& q) {
    // Scale by the largest component first so that huge quaternions do not overflow.
    const double m = std::max(std::max(std::abs(q[0]), std::abs(q[1])), std::max(std::abs(q[2]), std::abs(q[3])));
    const glm::dvec4 u = glm::normalize(q / m);
    const double w = u[0], x = u[1], y = u[2], z = u[3];
    glm::dmat3 R;  // R[column][row]
    R[0][0] = 1 - 2 * (y * y + z * z);
    R[1][0] = 2 * (x * y - w * z);
    R[2][0] = 2 * (x * z + w * y);
    R[0][1] = 2 * (x * y + w * z);
    R[1][1] = 1 - 2 * (x * x + z * z);
    R[2][1] = 2 * (y * z - w * x);
    R[0][2] = 2 * (x * z - w * y);
    R[1][2] = 2 * (y * z + w * x);
    R[2][2] = 1 - 2 * (x * x + y * y);
    return R;
}

}  // namespace detail

namespace {

struct ColmapCamera {
    int width = 0, height = 0;
    double fx = 0, fy = 0, cx = 0, cy = 0;
    std::string model;
    std::vector<double> distortion;
};

struct ColmapImage {
    std::string name;
    glm::dvec4 qvec{1, 0, 0, 0};
    glm::dvec3 tvec{0.0};
    int64_t camera_id = 0;
};

const detail::ColmapModel* model_by_id(int64_t id) {
    for (const auto& m : detail::colmap_models)
        if (m.id == id) return &m;
    return nullptr;
}

const detail::ColmapModel* model_by_name(std::string_view name) {
    for (const auto& m : detail::colmap_models)
        if (name == m.name) return &m;
    return nullptr;
}

[[noreturn]] void unsupported(const detail::ColmapModel& m, int64_t camera_id, const fs::path& file) {
    throw InputError(file.string(), "camera " + std::to_string(camera_id) + " uses the " + m.name +
                                        " model; only SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL and OPENCV "
                                        "are supported (undistort the images, e.g. with colmap image_undistorter)");
}

ColmapCamera make_camera(const detail::ColmapModel& m, int64_t camera_id, uint64_t width, uint64_t height,
                         const std::vector<double>& p, const fs::path& file) {
    if (m.id >= detail::colmap_supported_models) unsupported(m, camera_id, file);
    const std::string what = "camera " + std::to_string(camera_id);
    if (width == 0 || height == 0 || width > INT_MAX || height > INT_MAX)
        throw InputError(file.string(), what + ": invalid image size " + std::to_string(width) + "x" +
                                            std::to_string(height));
    for (double v : p)
        if (!std::isfinite(v)) throw InputError(file.string(), what + ": parameter is not finite");
    ColmapCamera c;
    c.width = int(width);
    c.height = int(height);
    c.model = m.name;
    const bool one_focal = m.id == 0 || m.id == 2 || m.id == 3;
    if (one_focal) {
        c.fx = c.fy = p[0];
        c.cx = p[1];
        c.cy = p[2];
        c.distortion.assign(p.begin() + 3, p.end());
    } else {
        c.fx = p[0];
        c.fy = p[1];
        c.cx = p[2];
        c.cy = p[3];
        c.distortion.assign(p.begin() + 4, p.end());
    }
    if (!(c.fx > 0) || !(c.fy > 0)) throw InputError(file.string(), what + ": focal length must be positive");
    return c;
}

// ---- binary ----------------------------------------------------------------------------

class BinaryCursor {
public:
    BinaryCursor(const std::vector<char>& data, const fs::path& file) : data_(data), file_(file) {}

    size_t remaining() const { return data_.size() - pos_; }

    template <class T>
    T read(const char* what) {
        need(sizeof(T), what);
        T v;
        std::memcpy(&v, data_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return v;
    }

    std::string read_cstring(const char* what) {
        const void* end = std::memchr(data_.data() + pos_, '\0', remaining());
        if (!end) truncated(what);
        const size_t len = size_t(static_cast<const char*>(end) - (data_.data() + pos_));
        std::string s(data_.data() + pos_, len);
        pos_ += len + 1;
        return s;
    }

    void skip(uint64_t n, const char* what) {
        need(n, what);
        pos_ += size_t(n);
    }

    // A count read from the file must fit the bytes that follow before anything is allocated.
    void check_count(uint64_t count, size_t min_record_size, const char* what) {
        if (count > remaining() / min_record_size)
            throw InputError(file_.string(), "claims " + std::to_string(count) + " " + what + " but only " +
                                                 std::to_string(remaining()) + " bytes follow (truncated or corrupt)");
    }

private:
    void need(uint64_t n, const char* what) {
        if (n > remaining()) truncated(what);
    }
    [[noreturn]] void truncated(const char* what) {
        throw InputError(file_.string(), "truncated: the file ends at byte " + std::to_string(data_.size()) +
                                             " while reading " + what);
    }

    const std::vector<char>& data_;
    const fs::path& file_;
    size_t pos_ = 0;
};

std::map<int64_t, ColmapCamera> read_cameras_bin(const fs::path& file) {
    const auto data = read_file(file);
    BinaryCursor in(data, file);
    const auto count = in.read<uint64_t>("the camera count");
    in.check_count(count, 4 + 4 + 8 + 8 + 3 * 8, "cameras");
    std::map<int64_t, ColmapCamera> cams;
    for (uint64_t i = 0; i < count; ++i) {
        const int64_t id = in.read<int32_t>("a camera id");
        const int32_t model_id = in.read<int32_t>("a camera model id");
        const auto width = in.read<uint64_t>("a camera width");
        const auto height = in.read<uint64_t>("a camera height");
        const detail::ColmapModel* m = model_by_id(model_id);
        if (!m)
            throw InputError(file.string(), "camera " + std::to_string(id) + " has unknown model id " +
                                                std::to_string(model_id));
        if (m->id >= detail::colmap_supported_models) unsupported(*m, id, file);
        std::vector<double> params(size_t(m->num_params));
        for (double& p : params) p = in.read<double>("camera parameters");
        if (!cams.emplace(id, make_camera(*m, id, width, height, params, file)).second)
            throw InputError(file.string(), "camera id " + std::to_string(id) + " appears twice");
    }
    return cams;
}

std::vector<ColmapImage> read_images_bin(const fs::path& file) {
    const auto data = read_file(file);
    BinaryCursor in(data, file);
    const auto count = in.read<uint64_t>("the image count");
    in.check_count(count, 4 + 4 * 8 + 3 * 8 + 4 + 1 + 8, "images");
    std::vector<ColmapImage> images(static_cast<size_t>(count));
    for (ColmapImage& im : images) {
        in.read<int32_t>("an image id");
        for (int k = 0; k < 4; ++k) im.qvec[k] = in.read<double>("a quaternion");
        for (int k = 0; k < 3; ++k) im.tvec[k] = in.read<double>("a translation");
        im.camera_id = in.read<int32_t>("an image's camera id");
        im.name = in.read_cstring("an image name");
        const auto points = in.read<uint64_t>("the 2D point count");
        in.check_count(points, 24, "2D points");
        in.skip(points * 24, "2D points");
    }
    return images;
}

// ---- text ------------------------------------------------------------------------------

struct Token {
    std::string_view text;
    size_t offset;  // in the line
};

std::vector<Token> split(std::string_view line) {
    std::vector<Token> out;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        const size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > start) out.push_back({line.substr(start, i - start), start});
    }
    return out;
}

class TextFile {
public:
    explicit TextFile(const fs::path& file) : file_(file), text_(read_text_file(file)) {}

    // Next line that is neither blank nor a comment; false at the end of the file.
    bool next_data_line(std::string_view& line) {
        while (next_line(line)) {
            const size_t first = line.find_first_not_of(" \t\r");
            if (first != std::string_view::npos && line[first] != '#') return true;
        }
        return false;
    }

    bool next_line(std::string_view& line) {
        if (pos_ >= text_.size()) return false;
        size_t end = text_.find('\n', pos_);
        if (end == std::string::npos) end = text_.size();
        line = std::string_view(text_).substr(pos_, end - pos_);
        pos_ = end + 1;
        ++line_no_;
        return true;
    }

    [[noreturn]] void fail(const std::string& reason) const {
        throw InputError(file_.string(), "line " + std::to_string(line_no_) + ": " + reason);
    }

    template <class T>
    T number(const Token& tok, const char* what) const {
        T v{};
        const char* first = tok.text.data();
        const char* last = first + tok.text.size();
        auto [ptr, ec] = std::from_chars(first, last, v);
        if (ec != std::errc() || ptr != last) fail(std::string("cannot read ") + what + " from '" + std::string(tok.text) + "'");
        return v;
    }

    const fs::path& file() const { return file_; }

private:
    fs::path file_;
    std::string text_;
    size_t pos_ = 0;
    int line_no_ = 0;
};

std::map<int64_t, ColmapCamera> read_cameras_txt(const fs::path& path) {
    TextFile in(path);
    std::map<int64_t, ColmapCamera> cams;
    std::string_view line;
    while (in.next_data_line(line)) {
        const auto tok = split(line);
        if (tok.size() < 4) in.fail("expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
        const auto id = in.number<int64_t>(tok[0], "a camera id");
        const detail::ColmapModel* m = model_by_name(tok[1].text);
        if (!m) in.fail("unknown camera model '" + std::string(tok[1].text) + "'");
        if (m->id >= detail::colmap_supported_models) unsupported(*m, id, path);
        const auto width = in.number<int64_t>(tok[2], "a width");
        const auto height = in.number<int64_t>(tok[3], "a height");
        if (tok.size() != size_t(4 + m->num_params))
            in.fail(std::string(m->name) + " needs " + std::to_string(m->num_params) + " parameters, found " +
                    std::to_string(tok.size() - 4));
        std::vector<double> params;
        for (size_t k = 4; k < tok.size(); ++k) params.push_back(in.number<double>(tok[k], "a camera parameter"));
        if (width <= 0 || height <= 0) in.fail("image size must be positive");
        if (!cams.emplace(id, make_camera(*m, id, uint64_t(width), uint64_t(height), params, path)).second)
            in.fail("camera id " + std::to_string(id) + " appears twice");
    }
    return cams;
}

std::vector<ColmapImage> read_images_txt(const fs::path& path) {
    TextFile in(path);
    std::vector<ColmapImage> images;
    std::string_view line;
    while (in.next_data_line(line)) {
        const auto tok = split(line);
        if (tok.size() < 10) in.fail("expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
        ColmapImage im;
        in.number<int64_t>(tok[0], "an image id");
        for (int k = 0; k < 4; ++k) im.qvec[k] = in.number<double>(tok[1 + k], "a quaternion component");
        for (int k = 0; k < 3; ++k) im.tvec[k] = in.number<double>(tok[5 + k], "a translation component");
        im.camera_id = in.number<int64_t>(tok[8], "a camera id");
        // The name is the rest of the line, so names with spaces survive.
        std::string_view name = line.substr(tok[9].offset);
        while (!name.empty() && (name.back() == ' ' || name.back() == '\t' || name.back() == '\r'))
            name.remove_suffix(1);
        im.name = std::string(name);
        images.push_back(std::move(im));
        in.next_line(line);  // the image's 2D points (possibly empty): not needed
    }
    return images;
}

fs::path pick(const fs::path& dir, const char* stem) {
    fs::path bin = dir / (std::string(stem) + ".bin"), txt = dir / (std::string(stem) + ".txt");
    if (fs::is_regular_file(bin)) return bin;
    if (fs::is_regular_file(txt)) return txt;
    throw InputError(bin.string(), std::string("no such file (nor ") + stem + ".txt): not a COLMAP model folder");
}

}  // namespace

std::vector<Camera> read_colmap(const fs::path& model_dir) {
    const fs::path cameras_file = pick(model_dir, "cameras");
    const fs::path images_file = pick(model_dir, "images");
    const auto cams =
        cameras_file.extension() == ".bin" ? read_cameras_bin(cameras_file) : read_cameras_txt(cameras_file);
    const auto images = images_file.extension() == ".bin" ? read_images_bin(images_file) : read_images_txt(images_file);

    std::vector<Camera> out;
    out.reserve(images.size());
    for (const ColmapImage& im : images) {
        const std::string what = "image '" + im.name + "'";
        auto it = cams.find(im.camera_id);
        if (it == cams.end())
            throw InputError(images_file.string(), what + " refers to camera id " + std::to_string(im.camera_id) +
                                                       ", which " + cameras_file.filename().string() +
                                                       " does not define");
        for (int k = 0; k < 4; ++k)
            if (!std::isfinite(im.qvec[k])) throw InputError(images_file.string(), what + ": quaternion is not finite");
        if (glm::length(im.qvec) < 1e-12)
            throw InputError(images_file.string(), what + ": quaternion has zero length");
        const ColmapCamera& c = it->second;
        Camera cam;
        cam.name = detail::image_stem(im.name);
        cam.width = c.width;
        cam.height = c.height;
        cam.fx = c.fx;
        cam.fy = c.fy;
        cam.cx = c.cx;
        cam.cy = c.cy;
        cam.model = c.model;
        cam.distortion = c.distortion;
        cam.R = detail::rotation_from_qvec(im.qvec);
        cam.t = im.tvec;
        detail::check_camera(cam, images_file);
        out.push_back(std::move(cam));
    }
    detail::finish_import(out, images_file);
    return out;
}

}  // namespace pg::data
