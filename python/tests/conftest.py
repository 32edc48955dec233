"""Shared fixtures: the CLI built beside the module (``$ASPERITY_CLI``) and
a scratch folder. Run by ``cargo test`` (crates/python/tests/pytest.rs)."""

import json
import os
import re
import subprocess
from pathlib import Path

import pytest


def _cli_path():
    p = os.environ.get("ASPERITY_CLI")
    if not p:
        pytest.exit("ASPERITY_CLI is not set: run these tests through `cargo test --workspace`", 2)
    return p


@pytest.fixture(scope="session")
def cli():
    """Runs the CLI with arguments; returns its JSON report (``--json``)."""
    exe = _cli_path()

    def run(*args, json_report=True, check=True):
        cmd = [exe] + (["--json"] if json_report else []) + [str(a) for a in args]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if check and p.returncode != 0:
            raise AssertionError(f"{' '.join(cmd)} failed:\n{p.stderr}")
        if not check:
            return p
        return json.loads(p.stdout) if json_report and p.stdout.strip() else p.stdout

    return run


@pytest.fixture
def tmp(tmp_path) -> Path:
    return tmp_path


def same_bytes_but_params(a, b):
    """Equal PLY files but for the parameter records in their headers (two
    ways of giving a job the same input: a scene file, its text)."""
    strip = lambda p: re.sub(rb"comment asperity-params [^\n]*\n", b"", Path(p).read_bytes())
    a, b = strip(a), strip(b)
    assert len(a) == len(b) and a == b, f"files differ ({len(a)} vs {len(b)} bytes)"


def same_bytes(a, b):
    a, b = Path(a).read_bytes(), Path(b).read_bytes()
    assert len(a) == len(b) and a == b, f"files differ ({len(a)} vs {len(b)} bytes)"
