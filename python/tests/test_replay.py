"""softfinger.replay against `host-sim replay` on the same input: every column equal (the
output's f32 values, as the CSV prints them), on each surface and method; bad input."""

import csv
import math
import subprocess

import numpy as np
import pytest

import softfinger


def motion(n=400, dt=0.001):
    """A roll about x then y with some spin: unit quaternions (w, x, y, z)."""
    t = np.arange(n) * dt
    ax = np.stack([np.sin(3 * t), np.cos(2 * t), 0.3 * np.ones(n)], axis=1)
    ax /= np.linalg.norm(ax, axis=1)[:, None]
    ang = 0.8 * np.sin(2 * math.pi * t)
    q = np.concatenate([np.cos(ang / 2)[:, None], np.sin(ang / 2)[:, None] * ax], axis=1)
    return t, q


def host_sim_replay(host_sim, tmp_path, t, q, *args):
    inp, out = tmp_path / "in.csv", tmp_path / "out.csv"
    with open(inp, "w") as f:
        f.write("t_s,qw,qx,qy,qz\n")
        for ti, qi in zip(t, q):
            f.write(",".join(repr(float(v)) for v in (ti, *qi)) + "\n")
    subprocess.run([host_sim, "replay", "--input", str(inp), "--out", str(out), *args],
                   check=True, capture_output=True)
    with open(out) as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("surface,method", [
    ("plane", "exact"), ("plane", "rpy"), ("plane", "paper-verbatim"),
    ("sphere", "exact"), ("bowl", "exact"), ("cylinder", "exact"),
])
def test_replay_equals_host_sim_replay(host_sim, tmp_path, surface, method):
    t, q = motion()
    rows = host_sim_replay(host_sim, tmp_path, t, q, "--surface", surface, "--method", method)
    ours = softfinger.replay(t, q, method=method, surface=surface, radius_m=0.01)
    assert len(rows) == len(t)
    for key, col in ours.items():
        theirs = [r[key] for r in rows]
        if key == "state":
            assert list(col) == theirs, key
        elif key == "t_s":
            assert np.array_equal(col, np.array(theirs, dtype=np.float64)), key
        else:
            # The CSV prints each f32 exactly (shortest round-trip form).
            assert np.array_equal(col.astype(np.float32), np.array(theirs, dtype=np.float32)), key


def test_replay_rejects_bad_input():
    t, q = motion(5)
    with pytest.raises(ValueError, match="method"):
        softfinger.replay(t, q, method="euler")
    with pytest.raises(ValueError, match="surface"):
        softfinger.replay(t, q, surface="cube")
    with pytest.raises(ValueError, match="radius_m"):
        softfinger.replay(t, q, radius_m=0.0)
    with pytest.raises(ValueError, match="bowl"):
        softfinger.replay(t, q, surface="bowl", object_radius_m=0.01)
    with pytest.raises(ValueError, match="empty"):
        softfinger.replay([], [])
    with pytest.raises(ValueError, match="rows"):
        softfinger.replay(t, q[:-1])
    with pytest.raises(ValueError, match="goes back"):
        softfinger.replay(t[::-1], q)
    with pytest.raises(ValueError, match="4"):
        softfinger.replay(t, q[:, :3])
    # The norm tolerance, 1e-3: just inside passes, just outside fails.
    ok = q.copy()
    ok[2] *= 1.0009
    softfinger.replay(t, ok)
    off = q.copy()
    off[2] *= 1.0011
    with pytest.raises(ValueError, match="norm"):
        softfinger.replay(t, off)
    nan = q.copy()
    nan[1, 0] = math.nan
    with pytest.raises(ValueError, match="finite"):
        softfinger.replay(t, nan)
