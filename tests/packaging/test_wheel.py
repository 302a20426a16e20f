"""A release a stranger can install: the wheel built from the sources, installed into a scratch venv
outside the checkout, runs the README's quick start, ``gym.make`` of every preset, every shipped model
and map, and ``pathplan-env`` (``--help``, ``evaluate`` on one episode) from a temporary directory,
opening no file of the checkout (an audit hook in ``installed_checks.py`` watches). The wheel holds the
two packages, the models and maps, the licence; never the run records of ``docs/results``.

Marked ``packaging`` (``pytest -m "not packaging"`` leaves it out); it runs by default. To stay fast it
installs the wheel with ``--no-deps`` into a venv whose dependencies are this interpreter's (a ``.pth``
line to its site-packages, read after the venv's own, whose editable hook is not run), and the venv
lives at a fixed path per checkout so that numba's cache of the installed sources (keyed by their
path and times, which the install sets from the wheel) survives from run to run."""

import hashlib
import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import zipfile
from datetime import datetime
from pathlib import Path

import pytest

pytestmark = pytest.mark.packaging

ROOT = Path(__file__).resolve().parents[2]
SOURCES = ("pyproject.toml", "README.md", "LICENSE", "pathplan_env", "agents")
MiB = 1024 * 1024
#: this interpreter's site-packages: the scratch venv's dependencies (read after its own site-packages)
DEPENDENCIES = sorted({sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]})


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """Built from a copy of what the wheel is made of, so the build writes nothing into the checkout."""
    work = tmp_path_factory.mktemp("wheel")
    (work / "src").mkdir()
    for name in SOURCES:
        source = ROOT / name
        if source.is_dir():
            shutil.copytree(source, work / "src" / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        else:
            shutil.copy2(source, work / "src" / name)
    built = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", str(work / "dist"), str(work / "src")],
                           capture_output=True, text=True, timeout=300)  # fmt: skip
    assert built.returncode == 0, built.stderr[-3000:]
    (found,) = (work / "dist").glob("pathplan_env-*.whl")
    return found


@pytest.fixture(scope="module")
def venv(wheel) -> Path:
    key = hashlib.sha1(str(ROOT).encode()).hexdigest()[:10]
    home = Path(tempfile.gettempdir()) / f"pathplan-env-wheel-{key}"
    shutil.rmtree(home, ignore_errors=True)
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(home)], check=True, timeout=120)
    python = home / "bin" / "python"
    purelib = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                             capture_output=True, text=True, check=True).stdout.strip()  # fmt: skip
    Path(purelib, "_pathplan_env_deps.pth").write_text("\n".join(DEPENDENCIES) + "\n")
    installed = subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "--no-deps", "--no-index", "-q", str(wheel)],
                               capture_output=True, text=True, timeout=300)  # fmt: skip
    assert installed.returncode == 0, installed.stderr[-3000:]
    with zipfile.ZipFile(wheel) as archive:  # the wheel's times on the installed files: numba's cache stays valid
        for info in archive.infolist():
            target = Path(purelib) / info.filename
            if target.is_file():
                stamp = datetime(*info.date_time).timestamp()
                os.utime(target, (stamp, stamp))
    return home


def _run(command, cwd, timeout=600):
    env = {key: value for key, value in os.environ.items() if key not in ("PYTHONPATH", "VIRTUAL_ENV", "PYTHONHOME")}
    env["SDL_VIDEODRIVER"] = "dummy"
    return subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


def test_the_wheel_holds_the_packages_models_and_maps_but_no_run_records(wheel):
    with zipfile.ZipFile(wheel) as archive:
        names = archive.namelist()
    tops = {name.split("/")[0] for name in names}
    assert tops == {"pathplan_env", "agents", wheel.name.split("-")[0] + "-" + wheel.name.split("-")[1] + ".dist-info"}, tops
    shipped = {Path(name).name for name in names if name.startswith(("agents/models/", "pathplan_env/maps/data/"))}
    on_disk = {path.name for folder in (ROOT / "agents" / "models", ROOT / "pathplan_env" / "maps" / "data") for path in folder.iterdir() if path.is_file()}
    assert shipped == on_disk
    assert not any("docs/" in name or "results" in name.split("/")[:-1] for name in names)
    assert any(name.endswith("dist-info/licenses/LICENSE") for name in names)
    assert wheel.stat().st_size < 10 * MiB  # the models are 3.5 MB; the 71 MB of run records stay out


def test_the_metadata_a_package_index_shows(wheel):
    with zipfile.ZipFile(wheel) as archive:
        meta = next(archive.read(n).decode() for n in archive.namelist() if n.endswith(".dist-info/METADATA"))
        entry_points = next(archive.read(n).decode() for n in archive.namelist() if n.endswith(".dist-info/entry_points.txt"))
    assert "License-Expression: MIT" in meta and "Classifier: Programming Language :: Python :: 3" in meta
    assert "Project-URL: Documentation" in meta and "Description-Content-Type: text/markdown" in meta
    assert "pathplan-env = agents.cli:main" in entry_points


def test_the_installed_package_runs_from_outside_the_checkout(venv, tmp_path):
    script = tmp_path / "installed_checks.py"
    shutil.copy2(Path(__file__).with_name("installed_checks.py"), script)
    readme = tmp_path / "README.md"
    shutil.copy2(ROOT / "README.md", readme)
    ran = _run([str(venv / "bin" / "python"), str(script), str(ROOT), str(readme), *DEPENDENCIES], cwd=tmp_path)
    assert ran.returncode == 0 and ran.stdout.rstrip().endswith("ok"), ran.stdout[-2000:] + ran.stderr[-4000:]


def test_the_console_command_runs_its_help_and_one_episode(venv, tmp_path):
    command = venv / "bin" / "pathplan-env"
    helped = _run([str(command), "--help"], cwd=tmp_path)
    assert helped.returncode == 0 and "evaluate" in helped.stdout and "render" in helped.stdout, helped.stderr[-2000:]
    out = tmp_path / "run"
    ran = _run([str(command), "evaluate", "--agents", "straight", "--scenarios", "random", "--delta-d", "0.5", "--episodes", "1", "--workers", "1",
                "--no-plots", "--no-limit", "--out", str(out)], cwd=tmp_path)  # fmt: skip
    assert ran.returncode == 0, ran.stderr[-3000:]
    assert (out / "summary.json").is_file() and "straight" in ran.stdout
    bad = _run([str(command), "evaluate", "--episodes", "0", "--out", str(tmp_path / "bad")], cwd=tmp_path)
    assert bad.returncode != 0 and "--episodes" in bad.stderr
