"""What the peer benchmarks share (bench_fem_scipy.py, bench_dgmpm_clawpack.py): one
`impact run` with its summary, the interleaved rounds, and the report of their medians."""
import json
import os
import subprocess
import tempfile

import numpy as np

IMPACT = os.environ.get("IMPACT_BIN", os.path.join(os.path.dirname(__file__), "..", "target", "release", "impact"))


def impact_run(scene: str, cells: int, method: str, t_end: float) -> dict:
    """`impact run <scene> --cells <cells> --method <method> --t-end <t_end>` without files
    or reference: its run record from summary.json (`wall_s` is the stepping time)."""
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([IMPACT, "run", scene, "--cells", str(cells), "--method", method,
                        "--no-files", "--no-reference", "--quiet", "--t-end", f"{t_end:e}",
                        "--out", out], check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f)["runs"][0]


def interleaved(rounds: int, peer, ours):
    """`peer()` and `ours()` alternated `rounds` times: their results as two lists."""
    results = [(peer(), ours()) for _ in range(rounds)]
    return [p for p, _ in results], [o for _, o in results]


def report(peer_label: str, peer, ours_label: str, ours, unit: str, digits: int, versus: str):
    """Print each side's results and median, and the ratio of the medians."""
    peer_median, ours_median = np.median(peer), np.median(ours)
    width = max(len(peer_label), len(ours_label)) + len(unit) + 2
    for label, values, median in [(peer_label, peer, peer_median), (ours_label, ours, ours_median)]:
        head = f"{label}, {unit}:".ljust(width + 1)
        print(head, " ".join(f"{v:.{digits}f}" for v in values), f"(median {median:.{digits}f})")
    print(f"impact is {peer_median / ours_median:.2f}x {versus}")
