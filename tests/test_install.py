"""pyrosgen as an installed package: its templates and the Coq library are
package data, found through pyrosgen.resources; outside a checkout the
library is built once into a cache folder, under a lock."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from pyrosgen import resources

REPO = Path(__file__).resolve().parent.parent
LANDSHARK = REPO / "examples" / "landshark" / "landshark_controller.yaml"


# --------------------------------------------------------------------------
# The cache build, on a tiny library


def _fake_library(root: Path, *, broken: bool = False) -> Path:
    src = root / "src"
    (src / "theories" / "lib").mkdir(parents=True)
    (src / "_CoqProject").write_text("-R theories ROSGen\ntheories/lib/A.v\n")
    body = "Definition a := 0. Fail Check b." if not broken else "Definition a := ."
    (src / "theories" / "lib" / "A.v").write_text(body + "\n")
    (src / "Makefile").write_text(
        "build:\n\tcoqc -R theories ROSGen theories/lib/A.v\n"
        "check-proof:\n\t@true\ncheck-assumptions:\n\t@true\n"
    )
    return src


def test_cache_build_once(tmp_path, monkeypatch):
    monkeypatch.setenv(resources.CACHE_ENV, str(tmp_path / "cache"))
    src = _fake_library(tmp_path)
    said: list[str] = []
    theories = resources.coq_theories(src=src, progress=said.append)
    assert (theories / "lib" / "A.vo").is_file()
    assert theories.parent.name.startswith("coq-") and len(said) == 1 and "once" in said[0]
    stamp = (theories / "lib" / "A.vo").stat().st_mtime_ns
    # Built once: a second call finds it and builds nothing.
    assert resources.coq_theories(src=src, progress=said.append) == theories
    assert len(said) == 1 and (theories / "lib" / "A.vo").stat().st_mtime_ns == stamp
    # No work folder left next to it.
    assert [p.name for p in (tmp_path / "cache").iterdir() if not p.name.startswith(".lock")] == [theories.parent.name]


def test_cache_build_concurrent_runs_build_once(tmp_path, monkeypatch):
    monkeypatch.setenv(resources.CACHE_ENV, str(tmp_path / "cache"))
    src = _fake_library(tmp_path)
    said: list[str] = []
    results: list[Path] = []
    threads = [threading.Thread(target=lambda: results.append(resources.coq_theories(src=src, progress=said.append)))
               for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(set(results)) == 1 and len(results) == 4
    assert len(said) == 1  # the lock: one build, the others found it built


def test_cache_build_failure_leaves_nothing(tmp_path, monkeypatch):
    monkeypatch.setenv(resources.CACHE_ENV, str(tmp_path / "cache"))
    src = _fake_library(tmp_path, broken=True)
    with pytest.raises(resources.LibraryBuildError) as info:
        resources.coq_theories(src=src)
    assert "building the Coq library failed" in str(info.value)
    assert [p.name for p in (tmp_path / "cache").iterdir() if not p.name.startswith(".lock")] == []


def test_digest_follows_the_sources(tmp_path):
    src = _fake_library(tmp_path)
    d1 = resources.coq_sources_digest(src)
    (src / "theories" / "lib" / "A.v").write_text("Definition a := 1.\n")
    assert resources.coq_sources_digest(src) != d1


# --------------------------------------------------------------------------
# A real, non-editable install


@pytest.mark.slow
def test_non_editable_install_works_from_another_folder(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", str(venv)], check=True)
    pip = subprocess.run(
        [str(venv / "bin" / "python"), "-m", "pip", "install", "-q", "--no-build-isolation", "--no-deps",
         "--disable-pip-version-check", str(REPO)],
        capture_output=True, text=True, check=False, timeout=600,
    )
    assert pip.returncode == 0, pip.stderr
    # pyrosgen's own dependencies (pyyaml, jinja2, rosbags, pycparser) come
    # from the project's environment, so that the test needs no network.
    deps = [p for p in sys.path if p.endswith("site-packages") and p.startswith(sys.prefix)]
    site = next((venv / "lib").glob("python3*/site-packages"))
    (site / "zz_project_deps.pth").write_text("\n".join(deps) + "\n")
    work = tmp_path / "elsewhere"
    work.mkdir()
    env = dict(os.environ, PYROSGEN_COQLIB=str(REPO / "coq" / "theories"), PYTHONPATH="")
    env.pop("PYTHONPATH")
    # The installed package, not the checkout, is what runs.
    where = subprocess.run(
        [str(venv / "bin" / "python"), "-c",
         "import pyrosgen.resources as r; print(r.PACKAGE_DIR); print(r.in_checkout()); "
         "print(len(list(r.coq_dir().glob('theories/*/*.v')))); print(r.templates_dir().is_dir())"],
        cwd=work, capture_output=True, text=True, check=True, env=env,
    ).stdout.split()
    assert str(venv) in where[0] and where[1] == "False"
    listed = [ln for ln in (REPO / "coq" / "_CoqProject").read_text().splitlines()
              if ln.startswith("theories/") and ln.count("/") == 2]
    assert int(where[2]) == len(listed) and where[3] == "True"
    exe = str(venv / "bin" / "pyrosgen")
    check = subprocess.run([exe, "check", str(LANDSHARK)], cwd=work, capture_output=True, text=True, env=env)
    assert check.returncode == 0 and "ok: node landshark_controller" in check.stdout, check.stderr
    gen = subprocess.run([exe, "generate", str(LANDSHARK), "-o", "out", "-q"], cwd=work,
                         capture_output=True, text=True, env=env, timeout=600)
    assert gen.returncode == 0, gen.stderr
    glue = (work / "out" / "landshark_controller_glue.c").read_text()
    golden = (REPO / "tests" / "generate" / "golden" / "landshark_controller_glue.c").read_text()
    assert glue == golden
