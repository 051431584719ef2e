"""Zoomed crops of the synthesized views around depth edges, beside the original view."""

import math
from pathlib import Path

from .experiment import settings_key, slug
from .runner import Run


def read_yuv_frame(path, width, height, frame=0, chroma="420", bit_depth=8):
    import numpy as np
    dtype = np.dtype(np.uint8) if bit_depth <= 8 else np.dtype("<u2")
    cw, ch = {"420": (width // 2, height // 2), "444": (width, height), "400": (0, 0)}[chroma]
    count = width * height + 2 * cw * ch
    data = np.fromfile(path, dtype=dtype, count=count, offset=frame * count * dtype.itemsize)
    if data.size != count:
        raise ValueError("%s: frame %d is beyond the end" % (path, frame))
    y = data[:width * height].reshape(height, width).astype(np.float64)
    if chroma == "400":
        return y, None, None
    u = data[width * height:width * height + cw * ch].reshape(ch, cw).astype(np.float64)
    v = data[width * height + cw * ch:].reshape(ch, cw).astype(np.float64)
    return y, u, v


def yuv_to_rgb(y, u, v, bit_depth=8):
    """BT.601 limited range to 8-bit RGB for display; chroma repeated to luma size."""
    import numpy as np
    scale = float(1 << (bit_depth - 8))
    y, u, v = y / scale, (u / scale if u is not None else None), (v / scale if v is not None else None)
    if u is None:
        u = v = np.full_like(y, 128.0)
    else:
        fy, fx = y.shape[0] // u.shape[0], y.shape[1] // u.shape[1]
        u = np.repeat(np.repeat(u, fy, axis=0), fx, axis=1)
        v = np.repeat(np.repeat(v, fy, axis=0), fx, axis=1)
    c, d, e = y - 16.0, u - 128.0, v - 128.0
    r = 1.164383 * c + 1.596027 * e
    g = 1.164383 * c - 0.391762 * d - 0.812968 * e
    b = 1.164383 * c + 2.017232 * d
    return np.clip(np.stack([r, g, b], axis=-1), 0, 255).astype(np.uint8)


def level_to_z(level, bit_depth, znear, zfar):
    """Z of a depth level: 1/Z = (L / Lmax) (1/Znear - 1/Zfar) + 1/Zfar (doc/depth.md), with the Znear
    and Zfar the tool reports for the view ("inf" allowed)."""
    inv_far = 0.0 if zfar == "inf" else 1.0 / float(zfar)
    return 1.0 / ((level / float((1 << bit_depth) - 1)) * (1.0 / float(znear) - inv_far) + inv_far)


def depth_edge_window(query, tool, cfg_path, settings, frame, size):
    """Centre (u, v) in the virtual view of the window with the strongest depth gradient of the first
    reference's depth, found by summing |gradient| over every window and moving the best one into the
    virtual camera with its nearest depth. Files, depth range and cameras are the tool's
    (`--print-config`)."""
    import numpy as np
    answer = query.print_config(tool, cfg_path.resolve(), settings)
    values, scene = answer["config"], answer["scene"]
    reference = scene["references"][0]
    width, height = scene["width"], scene["height"]
    bits = int(values["DepthBitDepth"])
    depth, _, _ = read_yuv_frame(reference["depth"], width, height, frame, values["DepthChromaFormat"], bits)
    gx = np.zeros_like(depth)
    gy = np.zeros_like(depth)
    gx[:, 1:] = np.abs(np.diff(depth, axis=1))
    gy[1:, :] = np.abs(np.diff(depth, axis=0))
    grad = np.minimum(gx + gy, float((1 << bits) - 1) / 4)  # a few huge steps should not win alone
    cw, ch = size
    integral = np.zeros((height + 1, width + 1))
    integral[1:, 1:] = grad.cumsum(0).cumsum(1)
    sums = integral[ch:, cw:] - integral[:-ch, cw:] - integral[ch:, :-cw] + integral[:-ch, :-cw]
    # Keep the window away from the borders, where warping leaves the frame.
    margin_x, margin_y = width // 8, height // 8
    inside = np.zeros(sums.shape, dtype=bool)
    inside[margin_y:max(margin_y + 1, sums.shape[0] - margin_y),
           margin_x:max(margin_x + 1, sums.shape[1] - margin_x)] = True
    sums = np.where(inside, sums, -1)
    top, left = np.unravel_index(int(np.argmax(sums)), sums.shape)
    u, v = left + cw / 2.0, top + ch / 2.0
    if int(values["DepthType"]) != 0:
        return u, v, (left, top)  # world-z depth: keep the reference position
    level = float(depth[top:top + ch, left:left + cw].max())  # the foreground's: the edge belongs to the nearer object
    z = level_to_z(level, bits, reference["znear"], reference["zfar"])
    source = query.camera(tool, cfg_path.resolve(), reference["camera"], settings)
    target = scene["virtual_camera"]
    k_s, r_s, k_t, r_t = (np.array(m, dtype=float) for m in (source["K"], source["R"], target["K"], target["R"]))
    x_cam = z * np.linalg.solve(k_s, np.array([u, v, 1.0]))
    world = r_s.T @ x_cam + np.array(source["centre"], dtype=float)
    p = k_t @ (r_t @ (world - np.array(target["centre"], dtype=float)))
    return p[0] / p[2], p[1] / p[2], (left, top)


def make_crop(report, crop, index):
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    exp = report.exp
    scene = next(s for s in exp.scenes if s.name == crop["scene"])
    camera = crop["camera"]
    frame = int(crop.get("frame", 0))
    cw, ch = crop.get("size", [96, 72])
    zoom = int(crop.get("zoom", 3))
    panels = []
    first_cfg = None
    for name in crop["methods"]:
        if name not in report.methods:
            continue  # its tool is not built
        method = report.methods[name]
        settings = settings_key(method.settings_list[0])
        row = report.row(scene.name, camera, method.tool, settings)
        output = Run(scene, camera, method.tool, method.settings_list[0]).output_path(exp.work)
        if not row or not output.is_file():
            raise RuntimeError("no kept output of %s for %s %s" % (name, scene.name, camera))
        first_cfg = first_cfg or (method.tool, scene.config_path(method.tool, camera), method.settings_list[0])
        panels.append((method.label, output, row))
    tool, cfg, settings = first_cfg
    answer = report.query.print_config(tool, cfg.resolve(), settings)
    values = answer["config"]
    width, height = answer["scene"]["width"], answer["scene"]["height"]
    chroma = answer["scene"]["chroma"]
    bits = int(values["TextureBitDepth"])
    if "at" in crop:  # a window chosen by hand, e.g. where two methods differ most
        left, top = (int(x) for x in crop["at"])
        left, top = min(max(left, 0), width - cw), min(max(top, 0), height - ch)
        where = "chosen in the experiment file (`at`)"
    else:
        u, v, (ref_left, ref_top) = depth_edge_window(report.query, tool, cfg, settings, frame, (cw, ch))
        left = int(round(min(max(u - cw / 2.0, 0), width - cw)))
        top = int(round(min(max(v - ch / 2.0, 0), height - ch)))
        where = ("where the left reference depth (%s) has its strongest gradient, window at (%d, %d) there, moved "
                 "into the virtual camera with the foreground's depth" % (values["LeftDepthMapName"], ref_left,
                                                                         ref_top))
    reference = scene.reference_path(camera, answer["scene"].get("reference"))
    images = [("original", reference, None)] + panels
    fig, axes = plt.subplots(1, len(images), figsize=(len(images) * cw * zoom / 100.0, ch * zoom / 100.0 + 0.45),
                             squeeze=False)
    for ax, (title, path, row) in zip(axes[0], images):
        y, uu, vv = read_yuv_frame(path, width, height, frame, chroma, bits)
        rgb = yuv_to_rgb(y, uu, vv, bits)[top:top + ch, left:left + cw]
        ax.imshow(rgb, interpolation="nearest")
        if row is not None:
            err = np.abs(y[top:top + ch, left:left + cw] -
                         read_yuv_frame(reference, width, height, frame, chroma, bits)[0][top:top + ch, left:left + cw])
            title = "%s\ncrop PSNR-Y %.2f dB" % (title, _psnr(err, bits))
        else:
            title = "%s (%s)\n%s" % (title, Path(path).name, "frame %d" % frame)
        ax.set_title(title, fontsize=7)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.subplots_adjust(left=0.005, right=0.995, bottom=0.01, top=0.86, wspace=0.03)
    name = crop.get("file", "crop_%s_%s.png" % (slug(scene.name.split("/")[-1]).lower(), camera))
    fig.savefig(report.image_dir / name, dpi=100)
    plt.close(fig)
    caption = "%s, %s, frame %d: a %dx%d window at (%d, %d) of the synthesized view, zoomed %dx, %s." % (
        scene.name, camera, frame, cw, ch, left, top, zoom, where)
    if crop.get("caption"):
        caption += " " + crop["caption"].strip()
    return name, caption


def _psnr(abs_err, bits):
    mse = float((abs_err ** 2).mean())
    peak = float((1 << bits) - 1)
    return math.inf if mse == 0 else 10 * math.log10(peak * peak / mse)


# ----------------------------------------------------------------------------------------------
