#!/usr/bin/env python3
"""`pip install` of the Python client (clients/python) into a fresh virtual environment, offline, then imports it
there: `import surfaced`, `surfaced.API_VERSION` (the API's info.version), the py.typed marker and the deprecated
`surfaced_client` shim.

The venv is made with --system-site-packages so that pip finds the installed setuptools (Debian's
python3-setuptools) without a package index, and pip runs with --no-index --no-build-isolation. Exits 77 (skipped,
said loudly) only when this Python cannot make a venv with pip (Debian: apt-get install python3-venv python3-pip).

    python3 tests/clients/client_install_test.py [REPO_ROOT]
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", ".."))
SKIP = 77


def run(cmd, **kwargs):
    print("$ " + " ".join(cmd), flush=True)
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300, **kwargs)


def main():
    with open(os.path.join(ROOT, "api", "openapi.json")) as f:
        api_version = json.load(f)["info"]["version"]
    with tempfile.TemporaryDirectory(prefix="surfaced-pip-") as tmp:
        venv = os.path.join(tmp, "venv")
        made = run([sys.executable, "-m", "venv", "--system-site-packages", venv])
        python = os.path.join(venv, "bin", "python")
        if made.returncode != 0 or not os.path.exists(python):
            print(made.stdout + made.stderr)
            print(f"SKIPPED: {sys.executable} cannot make a virtual environment (apt-get install python3-venv)")
            return SKIP
        pip = run([python, "-m", "pip", "--version"])
        if pip.returncode != 0:
            print(pip.stdout + pip.stderr)
            print(f"SKIPPED: no pip in a venv of {sys.executable} (apt-get install python3-pip)")
            return SKIP
        print(pip.stdout.strip())

        # a copy, so that the build (build/, *.egg-info) leaves the source tree alone
        source = os.path.join(tmp, "src")
        shutil.copytree(os.path.join(ROOT, "clients", "python"), source,
                        ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
        env = dict(os.environ, PIP_DISABLE_PIP_VERSION_CHECK="1", PIP_NO_INPUT="1")
        env.pop("PYTHONPATH", None)
        installed = run([python, "-m", "pip", "install", "--no-index", "--no-build-isolation", "--no-deps", source],
                        env=env)
        print(installed.stdout + installed.stderr)
        if installed.returncode != 0:
            print("FAILED: pip install of clients/python (it builds with the installed setuptools, 61 or later, "
                  "and wheel: apt-get install python3-setuptools python3-wheel)")
            return 1

        check = f"""
import inspect, os, sys, warnings
import surfaced
assert surfaced.__file__.startswith({venv!r}), surfaced.__file__
assert surfaced.API_VERSION == {api_version!r}, surfaced.API_VERSION
assert os.path.isfile(os.path.join(os.path.dirname(surfaced.__file__), "py.typed")), "py.typed not installed"
assert surfaced.is_compatible(surfaced.API_VERSION)
levels = inspect.signature(surfaced.Client.subdivide).parameters["levels"]
assert levels.kind is inspect.Parameter.KEYWORD_ONLY and levels.default == 1
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    import surfaced_client
assert issubclass(surfaced_client.Client, surfaced.Client)
assert any(issubclass(w.category, DeprecationWarning) for w in caught), "the shim does not say it is deprecated"
print("import surfaced:", surfaced.__version__, "API_VERSION", surfaced.API_VERSION, "from", surfaced.__file__)
"""
        # -I: no PYTHONPATH, no user site, not the current directory: only what the venv has
        imported = run([python, "-I", "-c", check], cwd=tmp, env=env)
        print(imported.stdout + imported.stderr)
        if imported.returncode != 0:
            print("FAILED: the installed package does not import as expected")
            return 1
    print("ok: pip install ./clients/python into a fresh venv, offline; import surfaced works")
    return 0


if __name__ == "__main__":
    sys.exit(main())
