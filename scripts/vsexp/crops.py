"""Zoomed crops where the methods differ: the truth, VSRS 4.2's output and the tools' outputs side by side."""

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
