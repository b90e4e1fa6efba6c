"""PNG previews of a Tyndall render and a Cycles render of the same scene,
each alone and side by side (Tyndall left, Cycles right, 4 px black gap):

    /work/bpy-venv/bin/python scenes/blender/side_by_side.py TYNDALL.exr CYCLES.exr OUT_PREFIX [EXPOSURE]

writes OUT_PREFIX-tyndall.png, OUT_PREFIX-cycles.png and
OUT_PREFIX-side-by-side.png. Both images get the same display transform:
linear radiance × 2^EXPOSURE (default 0), clamped to [0, 1], sRGB-encoded,
8 bits, as `tyndall render -o x.png` writes. Reads the EXRs with Blender's
image loader (bpy, the same venv as the other scripts here).
"""
import sys

import numpy as np

import bpy


def read_exr(path):
    """Linear RGB, top row first, float64 (h, w, 3)."""
    img = bpy.data.images.load(path, check_existing=False)
    w, h = img.size
    px = np.empty(w * h * 4, np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[::-1, :, :3].astype(np.float64)


def srgb(linear, exposure):
    x = np.clip(linear * 2.0 ** exposure, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def write_png(path, rgb):
    """rgb: sRGB-encoded values in [0, 1], top row first."""
    h, w = rgb.shape[:2]
    img = bpy.data.images.new("png", w, h, alpha=True, float_buffer=False)
    img.colorspace_settings.name = "sRGB"
    px = np.ones((h, w, 4), np.float32)
    px[:, :, :3] = np.round(rgb[::-1] * 255.0) / 255.0
    img.pixels.foreach_set(px.ravel())
    img.filepath_raw = path
    img.file_format = "PNG"
    img.save()
    bpy.data.images.remove(img)
    print("wrote", path)


def main():
    tyndall_exr, cycles_exr, prefix = sys.argv[1:4]
    exposure = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
    t = srgb(read_exr(tyndall_exr), exposure)
    c = srgb(read_exr(cycles_exr), exposure)
    if t.shape != c.shape:
        raise SystemExit(f"sizes differ: {t.shape} vs {c.shape}")
    gap = np.zeros((t.shape[0], 4, 3))
    write_png(prefix + "-tyndall.png", t)
    write_png(prefix + "-cycles.png", c)
    write_png(prefix + "-side-by-side.png", np.concatenate([t, gap, c], axis=1))


if __name__ == "__main__":
    main()
