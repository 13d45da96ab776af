#!/usr/bin/env python3
"""Writes tests/fixtures/malformed/cameras/: small broken camera files, one case per file or
folder. Every case must make pg::data::load_cameras throw an InputError whose message names
the case (tests/dataset/test_malformed_cameras.cpp). Standard library only; deterministic.

    python3 tools/make_malformed_cameras.py
"""
import json
import os
import shutil
import struct

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
OUT = os.path.join(ROOT, "tests", "fixtures", "malformed", "cameras")

PINHOLE, SIMPLE_RADIAL, FULL_OPENCV, OPENCV_FISHEYE = 1, 2, 6, 5


def cameras_bin(cams):
    """cams: list of (camera_id, model_id, width, height, params)."""
    out = struct.pack("<Q", len(cams))
    for cam_id, model_id, w, h, params in cams:
        out += struct.pack("<iiQQ", cam_id, model_id, w, h)
        out += struct.pack("<%dd" % len(params), *params)
    return out


def images_bin(images, count=None):
    """images: list of (image_id, qvec, tvec, camera_id, name, num_points2D)."""
    out = struct.pack("<Q", len(images) if count is None else count)
    for image_id, q, t, cam_id, name, npts in images:
        out += struct.pack("<i4d3di", image_id, *q, *t, cam_id)
        out += name.encode() + b"\0"
        out += struct.pack("<Q", npts)
        out += b"\0" * (24 * min(npts, 2))
    return out


GOOD_CAM = (1, PINHOLE, 64, 48, [50.0, 50.0, 32.0, 24.0])
GOOD_IMAGE = (1, [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 5.0], 1, "frame_001.png", 0)


def image(**kw):
    fields = dict(zip(["image_id", "q", "t", "cam_id", "name", "npts"], GOOD_IMAGE))
    fields.update(kw)
    return (fields["image_id"], fields["q"], fields["t"], fields["cam_id"], fields["name"], fields["npts"])


CAMERAS_TXT_HEADER = "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
IMAGES_TXT_HEADER = "# Image list with two lines of data per image:\n#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
GOOD_CAMERAS_TXT = CAMERAS_TXT_HEADER + "1 PINHOLE 64 48 50 50 32 24\n"
GOOD_IMAGES_TXT = IMAGES_TXT_HEADER + "1 1 0 0 0 0 0 5 1 frame_001.png\n\n"

INRIA_GOOD = {"id": 0, "img_name": "frame_001", "width": 64, "height": 48, "position": [0.0, 0.0, -5.0],
              "rotation": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], "fy": 50.0, "fx": 50.0}

NS_FRAME = {"file_path": "images/frame_001.png",
            "transform_matrix": [[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, -1, -5], [0, 0, 0, 1]]}
NS_GOOD = {"fl_x": 50.0, "fl_y": 50.0, "cx": 32.0, "cy": 24.0, "w": 64, "h": 48, "frames": [NS_FRAME]}


def inria(**changes):
    entry = dict(INRIA_GOOD)
    for k, v in changes.items():
        if v is None:
            entry.pop(k, None)
        else:
            entry[k] = v
    return [entry]


def nerfstudio(top=None, frame=None):
    doc = json.loads(json.dumps(NS_GOOD))
    for k, v in (top or {}).items():
        if v is None:
            doc.pop(k, None)
        else:
            doc[k] = v
    for k, v in (frame or {}).items():
        if v is None:
            doc["frames"][0].pop(k, None)
        else:
            doc["frames"][0][k] = v
    return doc


def write(rel, data):
    path = os.path.join(OUT, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def colmap_bin(case, cams, images):
    if cams is not None:
        write(case + "/cameras.bin", cams)
    if images is not None:
        write(case + "/images.bin", images)


def colmap_txt(case, cams, images):
    if cams is not None:
        write(case + "/cameras.txt", cams)
    if images is not None:
        write(case + "/images.txt", images)


def main():
    if os.path.isdir(OUT):
        shutil.rmtree(OUT)
    os.makedirs(OUT)

    good_cams = cameras_bin([GOOD_CAM])
    good_images = images_bin([GOOD_IMAGE])

    # COLMAP binary.
    colmap_bin("bin_truncated_cameras", good_cams[:-5], good_images)
    # Cut inside the name, past the minimum record size: the name has no terminating NUL.
    colmap_bin("bin_truncated_images_name", good_cams,
               images_bin([image(name="frame_with_a_long_name.png")])[:8 + 4 + 56 + 4 + 12])
    colmap_bin("bin_truncated_points2d", good_cams, images_bin([image(npts=1000)]))
    colmap_bin("bin_huge_camera_count", struct.pack("<Q", 1 << 40) + good_cams[8:], good_images)
    colmap_bin("bin_huge_image_count", good_cams, images_bin([GOOD_IMAGE], count=(1 << 62)))
    colmap_bin("bin_huge_points2d_count", good_cams, images_bin([image(npts=(1 << 63))])[:-48])
    colmap_bin("bin_unknown_camera_id", good_cams, images_bin([image(cam_id=7)]))
    colmap_bin("bin_unsupported_full_opencv", cameras_bin([(1, FULL_OPENCV, 64, 48, [50.0] * 12)]), good_images)
    colmap_bin("bin_unsupported_fisheye", cameras_bin([(1, OPENCV_FISHEYE, 64, 48, [50.0] * 8)]), good_images)
    colmap_bin("bin_unknown_model_id", cameras_bin([(1, 99, 64, 48, [50.0] * 4)]), good_images)
    colmap_bin("bin_nan_quaternion", good_cams, images_bin([image(q=[float("nan"), 0.0, 0.0, 0.0])]))
    colmap_bin("bin_zero_quaternion", good_cams, images_bin([image(q=[0.0, 0.0, 0.0, 0.0])]))
    colmap_bin("bin_inf_translation", good_cams, images_bin([image(t=[0.0, float("inf"), 5.0])]))
    colmap_bin("bin_nan_focal", cameras_bin([(1, PINHOLE, 64, 48, [float("nan"), 50.0, 32.0, 24.0])]), good_images)
    colmap_bin("bin_negative_focal", cameras_bin([(1, SIMPLE_RADIAL, 64, 48, [-50.0, 32.0, 24.0, 0.0])]),
               good_images)
    colmap_bin("bin_zero_width", cameras_bin([(1, PINHOLE, 0, 48, [50.0, 50.0, 32.0, 24.0])]), good_images)
    colmap_bin("bin_huge_height", cameras_bin([(1, PINHOLE, 64, 1 << 40, [50.0, 50.0, 32.0, 24.0])]), good_images)
    colmap_bin("bin_duplicate_camera_id", cameras_bin([GOOD_CAM, GOOD_CAM]), good_images)
    colmap_bin("bin_no_images", good_cams, images_bin([]))
    colmap_bin("bin_missing_images", good_cams, None)
    colmap_bin("bin_empty_files", b"", b"")
    colmap_bin("bin_duplicate_names", good_cams, images_bin([GOOD_IMAGE, image(image_id=2, name="other/frame_001.png")]))

    # COLMAP text.
    colmap_txt("txt_bad_number", CAMERAS_TXT_HEADER + "1 PINHOLE 64 48 50 5O 32 24\n", GOOD_IMAGES_TXT)
    colmap_txt("txt_missing_params", CAMERAS_TXT_HEADER + "1 PINHOLE 64 48 50 50 32\n", GOOD_IMAGES_TXT)
    colmap_txt("txt_extra_params", CAMERAS_TXT_HEADER + "1 SIMPLE_PINHOLE 64 48 50 32 24 0.1\n", GOOD_IMAGES_TXT)
    colmap_txt("txt_unsupported_fisheye", CAMERAS_TXT_HEADER + "1 OPENCV_FISHEYE 64 48 50 50 32 24 0 0 0 0\n",
               GOOD_IMAGES_TXT)
    colmap_txt("txt_unknown_model", CAMERAS_TXT_HEADER + "1 BROWN 64 48 50 50 32 24\n", GOOD_IMAGES_TXT)
    colmap_txt("txt_negative_width", CAMERAS_TXT_HEADER + "1 PINHOLE -64 48 50 50 32 24\n", GOOD_IMAGES_TXT)
    colmap_txt("txt_nan_cx", CAMERAS_TXT_HEADER + "1 PINHOLE 64 48 50 50 nan 24\n", GOOD_IMAGES_TXT)
    colmap_txt("txt_unknown_camera_id", GOOD_CAMERAS_TXT, IMAGES_TXT_HEADER + "1 1 0 0 0 0 0 5 3 frame_001.png\n\n")
    colmap_txt("txt_inf_translation", GOOD_CAMERAS_TXT, IMAGES_TXT_HEADER + "1 1 0 0 0 0 inf 5 1 frame_001.png\n\n")
    colmap_txt("txt_zero_quaternion", GOOD_CAMERAS_TXT, IMAGES_TXT_HEADER + "1 0 0 0 0 0 0 5 1 frame_001.png\n\n")
    colmap_txt("txt_short_image_line", GOOD_CAMERAS_TXT, IMAGES_TXT_HEADER + "1 1 0 0 0 0 0 5\n\n")
    colmap_txt("txt_only_comments", CAMERAS_TXT_HEADER, IMAGES_TXT_HEADER)
    colmap_txt("txt_missing_cameras", None, GOOD_IMAGES_TXT)

    # A scene folder whose sparse/0 is broken.
    colmap_bin("scene_broken_sparse/sparse/0", good_cams, good_images[:-3])

    # INRIA cameras.json.
    write("inria_truncated.json", json.dumps(inria())[:-20])
    write("inria_nan_position.json", json.dumps(inria(position=[0.0, float("nan"), -5.0])))  # Python writes NaN
    write("inria_huge_number.json", json.dumps(inria()).replace("50.0", "1e999"))
    write("inria_missing_fx.json", json.dumps(inria(fx=None)))
    write("inria_missing_img_name.json", json.dumps(inria(img_name=None)))
    write("inria_string_fy.json", json.dumps(inria(fy="50")))
    write("inria_zero_width.json", json.dumps(inria(width=0)))
    write("inria_fractional_height.json", json.dumps(inria(height=47.5)))
    write("inria_negative_focal.json", json.dumps(inria(fx=-50.0)))
    write("inria_rotation_2x3.json", json.dumps(inria(rotation=[[1, 0, 0], [0, 1, 0]])))
    write("inria_rotation_scaled.json", json.dumps(inria(rotation=[[2, 0, 0], [0, 2, 0], [0, 0, 2]])))
    write("inria_rotation_reflection.json", json.dumps(inria(rotation=[[-1, 0, 0], [0, 1, 0], [0, 0, 1]])))
    write("inria_position_2.json", json.dumps(inria(position=[0.0, 0.0])))
    write("inria_empty_array.json", "[]")
    write("inria_entry_not_object.json", json.dumps([INRIA_GOOD, 5]))
    write("inria_duplicate_names.json", json.dumps([INRIA_GOOD, dict(INRIA_GOOD, id=1)]))

    # nerfstudio transforms.json.
    write("ns_no_focal.json", json.dumps(nerfstudio(top={"fl_x": None, "fl_y": None})))
    write("ns_angle_without_size.json",
          json.dumps(nerfstudio(top={"fl_x": None, "fl_y": None, "w": None, "h": None, "camera_angle_x": 0.69})))
    write("ns_bad_angle.json", json.dumps(nerfstudio(top={"fl_x": None, "camera_angle_x": 4.0})))
    write("ns_negative_focal.json", json.dumps(nerfstudio(top={"fl_y": -50.0})))
    write("ns_matrix_3x3.json", json.dumps(nerfstudio(frame={"transform_matrix": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]})))
    write("ns_matrix_bad_last_row.json", json.dumps(nerfstudio(
        frame={"transform_matrix": [[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, -1, -5], [0, 0, 1, 1]]})))
    write("ns_matrix_nan.json", json.dumps(nerfstudio(
        frame={"transform_matrix": [[1, 0, 0, 0], [0, -1, 0, float("nan")], [0, 0, -1, -5], [0, 0, 0, 1]]})))
    write("ns_matrix_string.json", json.dumps(nerfstudio(
        frame={"transform_matrix": [[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, -1, "-5"], [0, 0, 0, 1]]})))
    write("ns_matrix_sheared.json", json.dumps(nerfstudio(
        frame={"transform_matrix": [[1, 0.5, 0, 0], [0, -1, 0, 0], [0, 0, -1, -5], [0, 0, 0, 1]]})))
    write("ns_missing_file_path.json", json.dumps(nerfstudio(frame={"file_path": None})))
    write("ns_missing_transform.json", json.dumps(nerfstudio(frame={"transform_matrix": None})))
    write("ns_fisheye.json", json.dumps(nerfstudio(top={"camera_model": "OPENCV_FISHEYE"})))
    write("ns_frames_not_array.json", json.dumps(nerfstudio(top={"frames": {"a": 1}})))
    write("ns_empty_frames.json", json.dumps(nerfstudio(top={"frames": []})))
    write("ns_width_string.json", json.dumps(nerfstudio(top={"w": "64"})))

    # Neither format, or nothing at all.
    write("empty.json", "")
    write("json_not_cameras.json", json.dumps({"cameras": []}))
    write("json_array_of_numbers.json", "[1, 2, 3]")
    write("not_a_camera_file.txt", "hello\n")
    write("folder_without_cameras/readme.md", "no cameras here\n")


if __name__ == "__main__":
    main()
