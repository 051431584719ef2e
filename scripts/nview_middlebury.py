#!/usr/bin/env python3
"""View 3 of every Middlebury 2005/2006 scene from views 1 and 5 against views 1, 2, 4 and 5.

Only views 1 and 5 come with depth; the depth of views 2 and 4 is synthesized first by ViewSyn from
views 1 and 5 (OutputVirtualDepthMapName). Prints a Markdown table (ours, 2 views; ours, 4 views;
difference). Usage: scripts/nview_middlebury.py [DATA_DIR] [WORK_DIR]
"""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VIEWSYN = os.path.join(ROOT, "Bin", "ViewSyn")


def psnr_y(args, cwd, summary):
    """Runs ViewSyn with a JSON summary (SummaryFile, doc/report.md) and returns its mean PSNR-Y."""
    run(args + ["SummaryFile=" + summary], cwd)
    with open(summary) as f:
        value = json.load(f)["mean"]["psnr_y"]
    if value is None:
        raise RuntimeError("no PSNR in %s (no reference view?)" % summary)
    return float(value)


def run(args, cwd):
    result = subprocess.run([VIEWSYN] + args, cwd=cwd, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(" ".join(args) + "\n" + result.stderr)
    return result.stdout


def scene_value(scene_dir, key):
    for line in open(os.path.join(scene_dir, "scene.txt")):
        if line.startswith(key + ":"):
            return line.split(":", 1)[1].split()[0]
    raise KeyError(key)


def main():
    data = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("VS_DATA_DIR", os.path.join(ROOT, "..", "shared", "data"))
    work = os.path.abspath(sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "out", "nview"))
    os.makedirs(work, exist_ok=True)
    rows = []
    for collection in ("middlebury2005", "middlebury2006"):
        folder = os.path.join(data, collection)
        for scene in sorted(os.listdir(folder)):
            d = os.path.join(folder, scene)
            out = os.path.join(work, scene)
            os.makedirs(out, exist_ok=True)
            two = psnr_y(["synth_view3_general.cfg", "OutputVirtualViewImageName=" + os.path.join(out, "two.yuv"),
                          "ReferenceVirtualViewImageName=view3.yuv"], d, os.path.join(out, "two.json"))
            for v in (2, 4):
                run(["synth_view%d_general.cfg" % v, "OutputVirtualViewImageName=" + os.path.join(out, "view%d_synth.yuv" % v),
                     "OutputVirtualDepthMapName=" + os.path.join(out, "depth%d.yuv" % v)], d)
            znear, zfar = scene_value(d, "Znear_mm"), scene_value(d, "Zfar_mm")
            config = os.path.join(out, "four.cfg")
            with open(config, "w") as f:
                for line in open(os.path.join(d, "synth_view3_general.cfg")):
                    key = line.split()[0] if line.split() else ""
                    if key.startswith("Left") or key.startswith("Right") or key in ("OutputVirtualViewImageName", "CameraParameterFile"):
                        continue
                    f.write(line)
                f.write("CameraParameterFile %s\n" % os.path.join(d, "cam_param.txt"))
                f.write("ReferenceCameraNames param_view1,param_view2,param_view4,param_view5\n")
                f.write("ReferenceViewImageNames %s\n" % ",".join(os.path.join(d, "view%d.yuv" % k) for k in (1, 2, 4, 5)))
                f.write("ReferenceDepthMapNames %s,depth2.yuv,depth4.yuv,%s\n" % (os.path.join(d, "depth1.yuv"), os.path.join(d, "depth5.yuv")))
                f.write("ReferenceNearestDepthValues %s\n" % ",".join([znear] * 4))
                f.write("ReferenceFarthestDepthValues %s\n" % ",".join([zfar] * 4))
                f.write("OutputVirtualViewImageName four.yuv\nReferenceVirtualViewImageName %s\n" % os.path.join(d, "view3.yuv"))
            four = psnr_y([config], out, os.path.join(out, "four.json"))
            rows.append((scene, two, four))
            print("%-12s %.2f %.2f" % (scene, two, four), file=sys.stderr)
    print("| scene | views 1, 5 | views 1, 2, 4, 5 | gain |")
    print("|---|---|---|---|")
    for scene, two, four in rows:
        print("| %s | %.2f | %.2f | %+.2f |" % (scene, two, four, four - two))
    n = len(rows)
    print("| **mean** | %.2f | %.2f | %+.2f |" % (sum(r[1] for r in rows) / n, sum(r[2] for r in rows) / n,
                                                sum(r[2] - r[1] for r in rows) / n))
    worse = [r[0] for r in rows if r[2] <= r[1]]
    print("\nscenes where 4 views are not better: %s" % (", ".join(worse) if worse else "none"))


if __name__ == "__main__":
    main()
