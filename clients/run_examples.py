#!/usr/bin/env python3
"""Runs the script clients' examples against a live server: starts `surfaced serve` on a free loopback port
(--port 0), runs every example of one client (python: clients/python/examples/*.py with python3, js:
clients/js/examples/*.mjs with node), stops the server. Exit status 0 only if every example passed.

    python3 clients/run_examples.py python|js SURFACED_BINARY [OUTPUT_DIR]
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    if len(sys.argv) < 3 or sys.argv[1] not in ("python", "js"):
        print(__doc__, file=sys.stderr)
        return 2
    lang, binary = sys.argv[1], sys.argv[2]
    out = sys.argv[3] if len(sys.argv) > 3 else tempfile.mkdtemp(prefix="surfaced-examples-")
    os.makedirs(out, exist_ok=True)
    if lang == "python":
        folder, suffix, interpreter = os.path.join(HERE, "python", "examples"), ".py", [sys.executable]
    else:
        node = shutil.which("node")
        if not node:
            print("node is needed for the JS client examples", file=sys.stderr)
            return 1
        folder, suffix, interpreter = os.path.join(HERE, "js", "examples"), ".mjs", [node]
    examples = sorted(f for f in os.listdir(folder) if f.endswith(suffix) and not f.startswith("_"))

    server = subprocess.Popen([binary, "serve", "--host", "127.0.0.1", "--port", "0", "--threads", "2"],
                              stdout=subprocess.PIPE, text=True)
    try:
        match = None
        for line in server.stdout:   # the first line normally; stops at EOF if the server exits
            match = re.search(r"listening on (http://[^/\s]+)/", line)
            if match:
                break
        if not match:
            print(f"surfaced did not start (exit status {server.wait()})", file=sys.stderr)
            return 1
        # keep reading the server's stdout so that it never blocks on a full pipe
        threading.Thread(target=lambda: [None for _ in server.stdout], daemon=True).start()
        url = match.group(1)
        print(f"server: {url}; outputs: {out}")
        failed = []
        for example in examples:
            print(f"== {lang} {example}", flush=True)
            env = dict(os.environ, SURFACED_EXAMPLE_OUT=out, PYTHONDONTWRITEBYTECODE="1")
            result = subprocess.run(interpreter + [example, url], cwd=folder, env=env, timeout=120)
            if result.returncode != 0:
                failed.append(example)
        print(f"{len(examples) - len(failed)} of {len(examples)} {lang} examples passed"
              + (f"; FAILED: {', '.join(failed)}" if failed else ""))
        # a clean SIGTERM shutdown exits 0 (under ASan/LSan a leak or error at exit would not)
        server.terminate()
        status = server.wait(timeout=30)
        if status != 0:
            print(f"surfaced exited with status {status} after SIGTERM", file=sys.stderr)
        return 1 if failed or not examples or status != 0 else 0
    finally:
        if server.poll() is None:
            server.kill()
            server.wait()


if __name__ == "__main__":
    sys.exit(main())
