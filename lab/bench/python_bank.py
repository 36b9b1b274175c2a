"""A 64-member bank built from Python (glint.build_bank) against glint-denoise bank, in the same
run, alternating, on the same input: the bindings' overhead (docs/lab/python.md).

    PYTHONPATH=build/python /usr/bin/python3 lab/bench/python_bank.py build --size 512 --repeat 5

Both build the default bank of 64 Latin-hypercube members (plus each filter's defaults) into a
cache folder of their own, on the machine's cores (2 here). Prints one JSON object: each run's
seconds of the bank's build (the CLI's own "seconds", Python's around build_bank) and of the
whole command (reading the EXR, building, writing the cache; the CLI's including its start),
the medians and Python's over the CLI's.
"""
import argparse
import json
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import glint

parser = argparse.ArgumentParser()
parser.add_argument("build", help="the build folder (its bin/glint-denoise)")
parser.add_argument("--size", type=int, default=512, help="the frame's width and height")
parser.add_argument("--spp", type=int, default=16)
parser.add_argument("--members", type=int, default=64)
parser.add_argument("--repeat", type=int, default=5)
args = parser.parse_args()

root = pathlib.Path(__file__).resolve().parents[2]
denoise = pathlib.Path(args.build) / "bin" / "glint-denoise"
work = pathlib.Path(tempfile.mkdtemp(prefix="glint-python-bank-"))

# The input: the Cornell box at size x size with half buffers.
scene = json.loads((root / "scenes" / "cornell" / "scene.json").read_text())
scene["film"] = {"width": args.size, "height": args.size}
scene["shapes"] = [{"obj": str(root / "scenes" / "cornell" / "cornell_box.obj")}]
(work / "scene.json").write_text(json.dumps(scene))
with glint.load_scene(work / "scene.json") as s:
    s.render(spp=args.spp, seed=1, half_buffers=True).frame.write_exr(work / "in.exr")

runs = {"cli_bank": [], "python_bank": [], "cli_total": [], "python_total": []}
for r in range(args.repeat):
    out = work / f"cli-{r}"
    t0 = time.perf_counter()
    cli = subprocess.run([str(denoise), "bank", str(work / "in.exr"), "--out", str(out), "--size",
                          str(args.members), "--json"], check=True, capture_output=True, text=True)
    runs["cli_total"].append(time.perf_counter() - t0)
    runs["cli_bank"].append(json.loads(cli.stdout)["seconds"])

    t0 = time.perf_counter()
    frame = glint.read_exr(work / "in.exr")
    t1 = time.perf_counter()
    bank = glint.build_bank(frame, size=args.members, cache_dir=work / f"python-{r}")
    t2 = time.perf_counter()
    runs["python_bank"].append(t2 - t1)
    runs["python_total"].append(t2 - t0)
    assert len(bank) == json.loads(cli.stdout)["members"]
    del bank, frame

medians = {k: statistics.median(v) for k, v in runs.items()}
report = {
    "size": args.size, "spp": args.spp, "members": args.members, "repeat": args.repeat,
    "runs": runs, "median": medians,
    "python_over_cli_bank": medians["python_bank"] / medians["cli_bank"],
    "python_over_cli_total": medians["python_total"] / medians["cli_total"],
}
json.dump(report, sys.stdout, indent=1)
print()
subprocess.run(["rm", "-rf", str(work)], check=True)
