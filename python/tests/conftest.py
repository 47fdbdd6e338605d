"""Shared fixtures: the repository's models and the `flexmbd` program to compare with."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def model(name: str) -> str:
    """The path of a scene or body model of models/."""
    return str(ROOT / "models" / name)


@pytest.fixture(scope="session")
def cli() -> str:
    """The `flexmbd` program (FLEXMBD_CLI, else target/release/flexmbd of this checkout)."""
    target = os.environ.get("CARGO_TARGET_DIR", str(ROOT / "target"))
    path = os.environ.get("FLEXMBD_CLI", os.path.join(target, "release", "flexmbd"))
    if not os.path.exists(path):
        pytest.fail(f"{path} not found: build it with `cargo build --release -p flexmbd-cli`")
    return path


def run_cli(cli: str, *args: str) -> subprocess.CompletedProcess:
    """Run the program, capturing its output."""
    return subprocess.run([cli, *args], capture_output=True, text=True, check=False)
