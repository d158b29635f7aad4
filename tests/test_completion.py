"""``pyrosgen --version`` and the bash completion script (``pyrosgen
completion``): bash itself runs the script and completes subcommands,
options, choices and folders."""

from __future__ import annotations

import hashlib
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from pyrosgen import __version__, cli
from pyrosgen.completion import bash_script

ROOT = Path(__file__).resolve().parent.parent


def test_version(capsys):
    """``pyrosgen X.Y.Z (ROSGen library <digest prefix>)``, exit 0, the
    prefix of the digest ``pyrosgen library`` prints whole."""
    assert cli.main(["--version"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"pyrosgen {__version__} (ROSGen library ")
    prefix = out.split("ROSGen library ")[1].rstrip(")\n")
    assert len(prefix) == 16 and int(prefix, 16) >= 0
    assert cli.main(["library"]) == 0
    whole = capsys.readouterr().out.split("sources SHA-256 ")[1].split()[0]
    assert whole.startswith(prefix)
    # the digest follows the library's sources
    theories = ROOT / "coq" / "theories"
    h = hashlib.sha256()
    from pyrosgen.proof.coqdriver import CoqDriver

    drv = CoqDriver(theories)
    for v in sorted(drv.library_sources(), key=lambda p: p.relative_to(theories).as_posix()):
        h.update(v.relative_to(theories).as_posix().encode() + b"\0" + v.read_bytes() + b"\0")
    assert h.hexdigest()[:16] == prefix


def test_version_from_the_shell():
    r = subprocess.run([sys.executable, "-m", "pyrosgen", "--version"], capture_output=True, text=True,
                       stdin=subprocess.DEVNULL, timeout=120)
    assert r.returncode == 0 and r.stdout.startswith(f"pyrosgen {__version__} (ROSGen library ") and not r.stderr


@pytest.fixture(scope="module")
def script(tmp_path_factory) -> Path:
    """The script as ``pyrosgen completion`` prints it."""
    r = subprocess.run([sys.executable, "-m", "pyrosgen", "completion"], capture_output=True, text=True,
                       stdin=subprocess.DEVNULL, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout == bash_script(cli.build_parser())
    path = tmp_path_factory.mktemp("completion") / "pyrosgen"
    path.write_text(r.stdout)
    return path


def complete(script: Path, words: list[str], cwd: Path = ROOT) -> list[str]:
    """What bash completes for the command line ``words`` (the last one
    being completed), with the script sourced."""
    bash = shutil.which("bash")
    assert bash is not None
    array = " ".join("'" + w.replace("'", "'\\''") + "'" for w in words)
    prog = (f"source '{script}'\n"
            "complete -p pyrosgen\n"
            f"COMP_WORDS=({array}); COMP_CWORD={len(words) - 1}\n"
            "_pyrosgen\n"
            "printf '%s\\n' \"${COMPREPLY[@]}\"\n")
    r = subprocess.run([bash, "--norc", "--noprofile", "-c", prog], capture_output=True, text=True, cwd=cwd,
                       stdin=subprocess.DEVNULL, timeout=60)
    assert r.returncode == 0, r.stderr
    first, *rest = r.stdout.splitlines()
    assert first == "complete -o filenames -F _pyrosgen pyrosgen"
    return sorted(w for w in rest if w)


def test_completes_subcommands(script):
    assert complete(script, ["pyrosgen", ""]) == sorted(
        ["check", "diagram", "generate", "build", "verify", "init", "library", "completion", "system"])
    assert complete(script, ["pyrosgen", "ve"]) == ["verify"]
    assert complete(script, ["pyrosgen", "-v", "bu"]) == ["build"]
    assert complete(script, ["pyrosgen", "--ver"]) == ["--verbose", "--version"]


def test_completes_options_and_values(script, tmp_path):
    assert complete(script, ["pyrosgen", "build", "m.yaml", "--con"]) == ["--controller"]
    assert complete(script, ["pyrosgen", "init", "--in"]) == ["--include"]
    assert complete(script, ["pyrosgen", "verify", "--k"]) == ["--kernel"]
    assert complete(script, ["pyrosgen", "generate", "m.yaml", "--k"]) == ["--keep-work"]
    assert complete(script, ["pyrosgen", "diagram", "m.yaml", "--format", "p"]) == ["pdf", "png"]
    # folders for --controller, files for a model
    (tmp_path / "ctl_a").mkdir()
    (tmp_path / "ctl_b").mkdir()
    (tmp_path / "ctl_model.yaml").write_text("")
    assert complete(script, ["pyrosgen", "build", "m.yaml", "--controller", "ctl"], cwd=tmp_path) == ["ctl_a", "ctl_b"]
    assert complete(script, ["pyrosgen", "check", "ctl"], cwd=tmp_path) == ["ctl_a", "ctl_b", "ctl_model.yaml"]
    assert complete(script, ["pyrosgen", "build", "m.yaml", "--cflags", ""], cwd=tmp_path) == []
    # --option=VALUE, as bash splits it
    assert complete(script, ["pyrosgen", "diagram", "m.yaml", "--format", "=", "s"]) == ["svg"]
    assert complete(script, ["pyrosgen", "diagram", "m.yaml", "--format", "="]) == ["dot", "pdf", "png", "svg"]
    assert complete(script, ["pyrosgen", "build", "m.yaml", "--controller", "=", "ctl_"], cwd=tmp_path) == \
        ["ctl_a", "ctl_b"]


def test_make_deps_installs_the_script(tmp_path):
    """The Makefile's rule (run by ``make deps``) writes the script into
    the virtual environment's bash-completion folder (here a stand-in
    venv, its pyrosgen installed)."""
    venv = tmp_path / "venv"
    venv.mkdir()
    (venv / ".installed").touch()
    target = venv / "share" / "bash-completion" / "completions" / "pyrosgen"
    r = subprocess.run(["make", "--no-print-directory", "-C", str(ROOT), "-o", "apt", f"VENV={venv}",
                        f"PY={sys.executable}", str(target)],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=120)
    assert r.returncode == 0, r.stderr
    assert target.read_text() == bash_script(cli.build_parser())
    assert complete(target, ["pyrosgen", "gen"]) == ["generate"]
