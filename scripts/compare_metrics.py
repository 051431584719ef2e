#!/usr/bin/env python3
"""Our YuvPsnr against the IV-PSNR reference software 7.1 (IVPSNR binary, built by
../shared/tools/build_qmiv.sh) on every Middlebury view-3 result (VSRS 4.2's general and 1D outputs
in ../shared/data/vsrs42-outputs, and ours rendered here by Bin/ViewSyn) and on the SceneGen demo
(Bin/ViewSyn's middle camera against SceneGen's ground truth, 10 frames). Prints both values of
every metric per file and the largest absolute difference per metric (doc/metrics.md).

usage: scripts/compare_metrics.py --reference /path/to/IVPSNR [--bin Bin] [--data ../shared/data]
                                  [--work /tmp/compare_metrics] [--scenes Art,Books] [--no-demo]
                                  [--meshrender] [--markdown FILE]
Exit code 0 when every difference is within the issue's tolerance (0.01 dB for PSNR, WS-PSNR and
IV-PSNR, 1e-4 for SSIM and MS-SSIM), 1 otherwise, 2 on bad arguments or a tool failure."""
import argparse
import csv
import os
import re
import subprocess
import sys

TOLERANCE = {"PSNR": 0.01, "WSPSNR": 0.01, "IVPSNR": 0.01, "SSIM": 1e-4, "MSSSIM": 1e-4}
OURS_KEYS = {"PSNR": "psnr", "WSPSNR": "wspsnr", "SSIM": "ssim", "MSSSIM": "msssim"}


def run(command, cwd=None):
    result = subprocess.run(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if result.returncode != 0:
        sys.stderr.write("failed: %s\n%s\n" % (" ".join(command), result.stdout[-2000:]))
        sys.exit(2)
    return result.stdout


def reference_values(binary, ref, test, width, height):
    """The reference's averages: {metric: [Y, U, V]} and {"IVPSNR": [v]}."""
    values = {}
    size = "%dx%d" % (width, height)
    common = [binary, "-i0", ref, "-i1", test, "-ps", size, "-bd", "8", "-cf", "420", "-v", "1"]
    # -erp also weights the reference's IV-PSNR rows, so WS-PSNR gets a run of its own.
    for metrics, extra in (("PSNR, IVPSNR, SSIM, MSSSIM", []), ("WSPSNR", ["-erp"])):
        out = run(common + ["-ml", metrics] + extra)
        for line in out.splitlines():
            m = re.match(r"Average\s+(\w+)\s+Y:Cb:Cr\s+([-\d.]+)(?: dB)?\s+([-\d.]+)(?: dB)?\s+([-\d.]+)", line)
            if m:
                values[m.group(1)] = [float(m.group(i)) for i in (2, 3, 4)]
            m = re.match(r"Average\s+IVPSNR\s+([-\d.]+)", line)
            if m:
                values["IVPSNR"] = [float(m.group(1))]
    return values


def our_values(bin_dir, ref, test, width, height, work):
    path = os.path.join(work, "ours.csv")
    run([os.path.join(bin_dir, "YuvPsnr"), ref, test, "%dx%d" % (width, height), "--metrics", "all", "--csv", path])
    with open(path) as f:
        rows = list(csv.DictReader(f))
    mean = rows[-1]
    values = {"IVPSNR": [float(mean["ivpsnr"])]}
    for metric, key in OURS_KEYS.items():
        values[metric] = [float(mean["%s_%s" % (key, p)]) for p in ("y", "u", "v")]
    return values


def scene_size(folder):
    text = open(os.path.join(folder, "scene.txt")).read()
    return int(re.search(r"^width:\s*(\d+)", text, re.M).group(1)), int(re.search(r"^height:\s*(\d+)", text, re.M).group(1))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--reference", required=True, help="the IV-PSNR reference software's IVPSNR binary")
    parser.add_argument("--bin", default=os.path.join(root, "Bin"))
    parser.add_argument("--data", default=os.path.join(root, "..", "shared", "data"))
    parser.add_argument("--work", default="/tmp/compare_metrics")
    parser.add_argument("--scenes", default="", help="comma-separated scene names (default: all)")
    parser.add_argument("--no-demo", action="store_true", help="leave the SceneGen demo out")
    parser.add_argument("--meshrender", action="store_true",
                        help="also render view 3 with Bin/MeshRender and compare it (about 1 s a scene)")
    parser.add_argument("--markdown", default="", help="also write the table as markdown to this file")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)

    outputs = os.path.join(args.data, "vsrs42-outputs")
    scenes = sorted(f[: -len("_view3_general.yuv")] for f in os.listdir(outputs) if f.endswith("_view3_general.yuv"))
    if args.scenes:
        scenes = [s for s in scenes if s in args.scenes.split(",")]
    pairs = []  # (label, ref, test, width, height)
    for scene in scenes:
        folder = next((os.path.join(args.data, year, scene) for year in ("middlebury2005", "middlebury2006")
                       if os.path.isdir(os.path.join(args.data, year, scene))), None)
        if folder is None:
            continue
        width, height = scene_size(folder)
        truth = os.path.join(folder, "view3.yuv")
        ours = os.path.join(args.work, scene + "_view3_general_ours.yuv")
        run([os.path.join(args.bin, "ViewSyn"), os.path.join(folder, "synth_view3_general.cfg"),
             "OutputVirtualViewImageName=" + ours])
        pairs.append((scene + " ViewSyn general", truth, ours, width, height))
        if args.meshrender:
            mesh = os.path.join(args.work, scene + "_view3_general_mesh.yuv")
            run([os.path.join(args.bin, "MeshRender"), os.path.join(folder, "synth_view3_general.cfg"),
                 "OutputVirtualViewImageName=" + mesh])
            pairs.append((scene + " MeshRender general", truth, mesh, width, height))
        for mode in ("general", "1d"):
            pairs.append((scene + " VSRS " + mode, truth, os.path.join(outputs, "%s_view3_%s.yuv" % (scene, mode)),
                          width, height))
    if not args.no_demo:
        demo = os.path.join(args.work, "demo")
        os.makedirs(demo, exist_ok=True)
        run([os.path.join(args.bin, "SceneGen"), "Scene=demo", "OutputFolder=" + demo])
        synth = os.path.join(demo, "synth_cam1_ours.yuv")
        run([os.path.join(args.bin, "ViewSyn"), os.path.join(demo, "viewsyn_cam1.cfg"),
             "OutputVirtualViewImageName=" + synth])
        pairs.append(("SceneGen demo ViewSyn (10 frames)", os.path.join(demo, "texture_cam1.yuv"), synth, 1024, 768))

    columns = [("PSNR", 0), ("PSNR", 1), ("PSNR", 2), ("IVPSNR", 0), ("WSPSNR", 0), ("WSPSNR", 1), ("WSPSNR", 2),
               ("SSIM", 0), ("SSIM", 1), ("SSIM", 2), ("MSSSIM", 0), ("MSSSIM", 1), ("MSSSIM", 2)]
    plane = "YUV"
    largest = {metric: 0.0 for metric in TOLERANCE}
    lines = ["| file | " + " | ".join("%s %s" % (m, plane[p]) if m != "IVPSNR" else m for m, p in columns) + " |",
             "|---|" + "---|" * len(columns)]
    for label, ref, test, width, height in pairs:
        ours = our_values(args.bin, ref, test, width, height, args.work)
        theirs = reference_values(args.reference, ref, test, width, height)
        cells = []
        for metric, p in columns:
            a, b = ours[metric][p], theirs[metric][p]
            largest[metric] = max(largest[metric], abs(a - b))
            digits = 4 if metric in ("PSNR", "WSPSNR", "IVPSNR") else 6
            cells.append("%.*f / %.*f" % (digits, a, digits, b))
        lines.append("| %s | %s |" % (label, " | ".join(cells)))
        print("%-40s IV-PSNR ours %.6f reference %.6f" % (label, ours["IVPSNR"][0], theirs["IVPSNR"][0]), flush=True)
    print()
    print("largest |ours - reference| over %d files:" % len(pairs))
    ok = True
    for metric, value in largest.items():
        within = value <= TOLERANCE[metric]
        ok = ok and within
        print("  %-7s %.3g  (tolerance %g) %s" % (metric, value, TOLERANCE[metric], "ok" if within else "OVER"))
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write("Each cell: ours / reference (IV-PSNR software 7.1).\n\n" + "\n".join(lines) + "\n\n")
            f.write("Largest |ours - reference| over %d files: " % len(pairs) +
                    ", ".join("%s %.3g" % (m, v) for m, v in largest.items()) + "\n")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
