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


# The rule that picks a crop's window (doc: the report's crop captions say it too).
FLAT_STD = 12.0                 # the reference's luma standard deviation in the window at least this (8-bit levels)
MID_LUMA = (60.0, 200.0)        # and its mean luma within this range: textured, mid-brightness areas only


def window_sums(image, cw, ch):
    """Sum of image over every cw x ch window (top-left at [row, column])."""
    import numpy as np
    integral = np.zeros((image.shape[0] + 1, image.shape[1] + 1))
    integral[1:, 1:] = image.cumsum(0).cumsum(1)
    return integral[ch:, cw:] - integral[:-ch, cw:] - integral[ch:, :-cw] + integral[:-ch, :-cw]


def differing_window(reference, outputs, cw, ch, bits):
    """(left, top, spread) of the window where the panels' errors differ most: the largest difference between
    the highest and the lowest mean squared luma error of the panels over the window, among windows whose
    reference is textured and of middle brightness (FLAT_STD, MID_LUMA, scaled to the bit depth) and which
    keep width/8 and height/8 away from the borders (where every method lacks data)."""
    import numpy as np
    scale = float(1 << (bits - 8))
    n = float(cw * ch)
    mse = np.stack([window_sums((o - reference) ** 2, cw, ch) / n for o in outputs])
    spread = mse.max(axis=0) - mse.min(axis=0)
    mean_y = window_sums(reference, cw, ch) / n
    std_y = np.sqrt(np.maximum(window_sums(reference ** 2, cw, ch) / n - mean_y ** 2, 0.0))
    ok = (std_y >= FLAT_STD * scale) & (mean_y >= MID_LUMA[0] * scale) & (mean_y <= MID_LUMA[1] * scale)
    height, width = reference.shape
    inside = np.zeros(ok.shape, dtype=bool)
    my, mx = height // 8, width // 8
    inside[my:max(my + 1, ok.shape[0] - my), mx:max(mx + 1, ok.shape[1] - mx)] = True
    score = np.where(ok & inside, spread, -1.0)
    if score.max() < 0:
        score = np.where(inside, spread, -1.0)  # nothing qualifies: the largest spread anyway
    top, left = np.unravel_index(int(np.argmax(score)), score.shape)
    return int(left), int(top), float(spread[top, left])


def make_crop(report, crop, index):
    import textwrap
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
        panels.append((method.label, output))
    if crop.get("vsrs"):
        output = exp.vsrs_outputs / ("%s_%s_%s.yuv" % (scene.name.split("/")[-1], camera, crop["vsrs"]))
        if output.is_file():
            panels.insert(0, ("VSRS 4.2 %s (its own output)" % crop["vsrs"], output))
    tool, cfg, settings = first_cfg
    answer = report.query.print_config(tool, cfg.resolve(), settings)
    values = answer["config"]
    width, height = answer["scene"]["width"], answer["scene"]["height"]
    chroma = answer["scene"]["chroma"]
    bits = int(values["TextureBitDepth"])
    reference = scene.reference_path(camera, answer["scene"].get("reference"))
    truth = read_yuv_frame(reference, width, height, frame, chroma, bits)
    pictures = [read_yuv_frame(path, width, height, frame, chroma, bits) for _, path in panels]
    if "at" in crop:  # a window chosen by hand
        left, top = (int(x) for x in crop["at"])
        left, top = min(max(left, 0), width - cw), min(max(top, 0), height - ch)
        where = "chosen in the experiment file (`at`)"
    else:
        left, top, spread = differing_window(truth[0], [p[0] for p in pictures], cw, ch, bits)
        where = ("where the panels' errors differ most: the largest difference between the highest and the lowest "
                 "mean squared luma error of the panels (%.0f here), among windows whose truth has a luma standard "
                 "deviation of at least %g and a mean luma within %g-%g (no flat, dark or bright areas), away "
                 "from the borders by an eighth of the frame" % (spread, FLAT_STD, MID_LUMA[0], MID_LUMA[1]))
    images = [("truth (%s)" % Path(reference).name, truth, None)] + [
        (label, picture, picture[0]) for (label, _), picture in zip(panels, pictures)]
    fig, axes = plt.subplots(1, len(images), figsize=(len(images) * cw * zoom / 100.0, ch * zoom / 100.0 + 0.5),
                             squeeze=False)
    for ax, (title, (y, uu, vv), luma) in zip(axes[0], images):
        rgb = yuv_to_rgb(y, uu, vv, bits)[top:top + ch, left:left + cw]
        ax.imshow(rgb, interpolation="nearest")
        title = "\n".join(textwrap.wrap(title, 34)[:2])
        if luma is not None:
            err = np.abs(luma[top:top + ch, left:left + cw] - truth[0][top:top + ch, left:left + cw])
            title = "%s\nPSNR-Y on the crop %.2f dB" % (title, _psnr(err, bits))
        ax.set_title(title, fontsize=6.5)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.subplots_adjust(left=0.005, right=0.995, bottom=0.01, top=0.78, wspace=0.03)
    name = crop.get("file", "crop_%s_%s.png" % (slug(scene.name.split("/")[-1]).lower(), camera))
    fig.savefig(report.image_dir / name, dpi=200)
    plt.close(fig)
    caption = "%s, %s, frame %d: the %dx%d window at (%d, %d), zoomed %dx, %s." % (
        scene.name, camera, frame, cw, ch, left, top, zoom, where)
    if crop.get("caption"):
        caption += " " + crop["caption"].strip()
    return name, caption


def _psnr(abs_err, bits):
    mse = float((abs_err ** 2).mean())
    peak = float((1 << bits) - 1)
    return math.inf if mse == 0 else 10 * math.log10(peak * peak / mse)


# ----------------------------------------------------------------------------------------------
