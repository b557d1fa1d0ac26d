"""GET /healthz, /livez, /readyz, /metrics and /openapi.json; the server's API version against the client's."""
from _common import check, client  # also puts this checkout's package first on sys.path

import surfaced  # noqa: E402

check(client.healthz() == {"status": "ok"}, "healthz ok")
check(client.livez() == {"status": "ok"} and client.readyz() == {"status": "ready"}, "livez ok, readyz ready")
check("surfaced_http_requests_total" in client.metrics(), "metrics: Prometheus text")
doc = client.openapi()
check(doc["openapi"].startswith("3.1") and "/subdivide" in doc["paths"], f"{len(doc['paths'])} paths documented")
version = client.check_server_version()
check(surfaced.is_compatible(version, surfaced.API_VERSION),
      f"server implements API {version}; client made for {surfaced.API_VERSION}")
check(not surfaced.is_compatible("1.0.0", "0.1.0") and surfaced.is_compatible("1.3.0", "1.2.5"),
      "semantic-version compatibility")
