"""Fixtures: the host-sim binary, and a fresh virtual device (`host-sim serve`) per test on a
free loopback port, stopped afterwards."""

import os
import pathlib
import re
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def host_sim():
    """Path of the host-sim binary: $SOFTFINGER_HOST_SIM, else the workspace's build."""
    env = os.environ.get("SOFTFINGER_HOST_SIM")
    candidates = [pathlib.Path(env)] if env else [ROOT / "target" / p / "host-sim" for p in ("release", "debug")]
    for c in candidates:
        if c.is_file():
            return str(c)
    if os.environ.get("CI"):
        pytest.fail(f"no host-sim binary at {candidates} (build it: cargo build -p host-sim)")
    pytest.skip("no host-sim binary (cargo build -p host-sim, or set SOFTFINGER_HOST_SIM)")


@pytest.fixture
def server(host_sim):
    """A fresh virtual device; yields its target string."""
    p = subprocess.Popen(
        [host_sim, "serve", "--listen", "127.0.0.1:0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        line = p.stdout.readline()
        m = re.search(r"listening on (\S+:\d+)", line)
        assert m, f"host-sim serve said: {line!r}"
        yield "tcp:" + m.group(1)
    finally:
        p.kill()
        p.wait()
