"""Shared by the examples: the server URL (argv[1] or $SURFACED_URL) and an output directory."""
import os
import sys

# the package from this checkout (clients/python/surfaced), also when another version is installed
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from surfaced import Client  # noqa: E402

URL = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SURFACED_URL", "http://127.0.0.1:8080")
OUT = os.environ.get("SURFACED_EXAMPLE_OUT", ".")
client = Client(URL)


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    if not condition:
        sys.exit(1)
