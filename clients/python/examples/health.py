"""GET /healthz and GET /openapi.json."""
from _common import check, client

check(client.healthz() == {"status": "ok"}, "healthz ok")
doc = client.openapi()
check(doc["openapi"].startswith("3.1") and "/subdivide" in doc["paths"], f"{len(doc['paths'])} paths documented")
