"""The pool's split warm-up: one worker compiles the tree loop's helpers first,
with exactly the types the loop passes them (so no variant is compiled twice)."""

import subprocess
import sys
from pathlib import Path

from navlab import warmup

SRC = str(Path(__file__).resolve().parents[1] / "src")


def test_the_helpers_are_warmed_with_the_signatures_the_tree_loop_uses(tmp_path):
    """In a cold cache (a kernel loaded from the cache shows no signatures of
    its callees): the loop's compile must find every helper already compiled."""
    code = ("import navlab; from navlab import warmup; from navlab.sampling import bucket_grid as G, "
            "tree_kernel as K; warmup._warm_tree_helpers(); "
            "navlab.plan('trap', planner='rrt_star', max_iter=300, seed=0); "
            "print([len(f.signatures) for f in (G.nearest, G.near, G.insert, K._shift_subtree)])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                         env={"PYTHONPATH": SRC, "NUMBA_CACHE_DIR": str(tmp_path)})
    # one variant each (the candidate heap is inlined into the loop)
    assert out.stdout.strip() == "[1, 1, 1, 1]", out.stderr[-2000:]


def test_only_the_first_worker_claims_the_helpers(tmp_path, monkeypatch):
    monkeypatch.setattr(warmup, "_SIBLINGS", {"helpers_first": False, "helpers_done": False, "lock": None})
    lock = str(tmp_path / "warm-up.lock")
    warmup.claim_warm_up_role(lock)
    try:
        assert warmup._SIBLINGS["helpers_first"]
        sibling = ("import sys; from navlab import warmup; warmup.claim_warm_up_role(sys.argv[1]); "
                   "print(warmup._SIBLINGS['helpers_first'])")
        out = subprocess.run([sys.executable, "-c", sibling, lock], capture_output=True, text=True,
                             env={"PYTHONPATH": SRC}, timeout=120)
        assert out.stdout.strip() == "False", out.stderr
    finally:
        import os

        os.close(warmup._SIBLINGS["lock"])
