#!/usr/bin/env python3
"""Checks the Kubernetes manifests in deploy/ against each other and against the service they deploy.

Run by ctest (deploy_manifests) with Debian's python3 + python3-yaml:  python3 tests/deploy/manifests_test.py
Checks: every manifest is listed in the kustomization and has a known kind/apiVersion; the Deployment's probes use
GET routes that api/openapi.json documents; the container port is the one the Dockerfile exposes and serves on;
requests and limits are set and limits >= requests; the pod runs as the image's non-root user with no privilege
escalation; the grace period covers the preStop pause; the Service, HPA, PDB and Ingress point at what exists;
the ingress body-size annotation equals the service's --max-body-mb; every flag in args is one `serve` accepts.
"""
import json
import os
import re
import sys
import unittest

import yaml

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DEPLOY = os.path.join(ROOT, "deploy")

KNOWN_KINDS = {
    "Deployment": "apps/v1",
    "Service": "v1",
    "HorizontalPodAutoscaler": "autoscaling/v2",
    "PodDisruptionBudget": "policy/v1",
    "Ingress": "networking.k8s.io/v1",
}

_SUFFIX = {"": 1, "k": 1e3, "M": 1e6, "G": 1e9, "T": 1e12, "P": 1e15, "E": 1e18,
           "Ki": 2**10, "Mi": 2**20, "Gi": 2**30, "Ti": 2**40, "Pi": 2**50, "Ei": 2**60, "m": 1e-3}


def quantity(value):
    """A Kubernetes resource quantity ("500m", "1", "1.5", "4Gi", "128974848", "129e6") as a float."""
    text = str(value).strip()
    match = re.fullmatch(r"([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)(Ki|Mi|Gi|Ti|Pi|Ei|[kMGTPEm]?)", text)
    if not match:
        raise ValueError(f"not a Kubernetes quantity: {value!r}")
    return float(match.group(1)) * _SUFFIX[match.group(2)]


def nginx_size_mib(value):
    """An nginx size ("64m", "1g", "512k", "1048576") in MiB."""
    match = re.fullmatch(r"(\d+)([kKmMgG]?)", str(value).strip())
    if not match:
        raise ValueError(f"not an nginx size: {value!r}")
    scale = {"": 1 / 2**20, "k": 1 / 2**10, "m": 1, "g": 2**10}[match.group(2).lower()]
    return int(match.group(1)) * scale


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def load_manifests():
    """{kind: [document, ...]} from every .yaml in deploy/ except the kustomization; also the file of each."""
    by_kind, files = {}, {}
    for name in sorted(os.listdir(DEPLOY)):
        if not name.endswith((".yaml", ".yml")) or name.startswith("kustomization."):
            continue
        for doc in yaml.safe_load_all(read(os.path.join(DEPLOY, name))):
            if doc is None:
                continue
            by_kind.setdefault(doc.get("kind"), []).append(doc)
            files.setdefault(name, []).append(doc)
    return by_kind, files


def dockerfile_runtime_stage():
    """The instructions of the Dockerfile's last stage, as (KEYWORD, rest) with continuation lines joined."""
    text = re.sub(r"\\\n", " ", read(os.path.join(ROOT, "Dockerfile")))
    stages, current = [], None
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        keyword, _, rest = line.partition(" ")
        if keyword.upper() == "FROM":
            current = []
            stages.append(current)
        if current is not None:
            current.append((keyword.upper(), rest.strip()))
    return stages[-1]


def serve_flags():
    """The options `surfaced serve --help` lists (from server/cli/serve.cpp's help text)."""
    text = read(os.path.join(ROOT, "server", "cli", "serve.cpp"))
    start = text.index("kServeHelp")
    end = text.index(')";', start)
    return set(re.findall(r"^\s+(--[a-z][a-z0-9-]*)", text[start:end], re.M))


class Manifests(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.by_kind, cls.files = load_manifests()
        cls.openapi = json.loads(read(os.path.join(ROOT, "api", "openapi.json")))
        cls.runtime = dockerfile_runtime_stage()

    def one(self, kind):
        docs = self.by_kind.get(kind, [])
        self.assertEqual(len(docs), 1, f"expected exactly one {kind} in deploy/")
        return docs[0]

    def container(self):
        containers = self.one("Deployment")["spec"]["template"]["spec"]["containers"]
        self.assertEqual(len(containers), 1)
        return containers[0]

    def named_port(self, port):
        """A probe/targetPort (name or number) -> the container port number it means."""
        ports = self.container()["ports"]
        if isinstance(port, int):
            self.assertIn(port, [p["containerPort"] for p in ports])
            return port
        matches = [p["containerPort"] for p in ports if p.get("name") == port]
        self.assertEqual(len(matches), 1, f"no container port named {port!r}")
        return matches[0]

    def test_kinds_and_kustomization(self):
        for kind, docs in self.by_kind.items():
            self.assertIn(kind, KNOWN_KINDS, f"unexpected kind {kind}")
            for doc in docs:
                self.assertEqual(doc["apiVersion"], KNOWN_KINDS[kind], kind)
                self.assertEqual(doc["metadata"]["name"], "surfaced")
        for kind in ("Deployment", "Service", "HorizontalPodAutoscaler"):
            self.one(kind)
        kustomization = yaml.safe_load(read(os.path.join(DEPLOY, "kustomization.yaml")))
        self.assertEqual(sorted(kustomization["resources"]), sorted(self.files))

    def test_probes_are_documented_get_routes(self):
        paths = self.openapi["paths"]
        c = self.container()
        for probe in ("livenessProbe", "readinessProbe"):
            get = c[probe]["httpGet"]
            self.assertTrue(get["path"] in paths, f"{probe} path {get['path']} is not in api/openapi.json")
            self.assertIn("get", paths[get["path"]])
            self.assertEqual(self.named_port(get["port"]), 8080)
        self.assertEqual(c["livenessProbe"]["httpGet"]["path"], "/livez")
        self.assertEqual(c["readinessProbe"]["httpGet"]["path"], "/readyz")

    def test_port_matches_the_image(self):
        exposed = [rest for kw, rest in self.runtime if kw == "EXPOSE"]
        self.assertEqual(exposed, ["8080"])
        entrypoint = json.loads(next(rest for kw, rest in self.runtime if kw == "ENTRYPOINT"))
        self.assertEqual(entrypoint[:2], ["surfaced", "serve"])
        self.assertEqual(entrypoint[entrypoint.index("--port") + 1], "8080")
        self.assertEqual(entrypoint[entrypoint.index("--host") + 1], "0.0.0.0")
        self.assertEqual([p["containerPort"] for p in self.container()["ports"]], [8080])

    def test_args_are_serve_options(self):
        flags = serve_flags()
        self.assertIn("--max-body-mb", flags)
        for arg in self.container().get("args", []):
            if arg.startswith("--"):
                self.assertIn(arg.split("=")[0], flags, f"surfaced serve has no option {arg}")
                self.assertNotIn(arg.split("=")[0], ("--host", "--port"), "the image's entrypoint sets these")

    def test_resources(self):
        resources = self.container()["resources"]
        for key in ("cpu", "memory"):
            request = quantity(resources["requests"][key])
            limit = quantity(resources["limits"][key])
            self.assertGreater(request, 0, key)
            self.assertGreaterEqual(limit, request, f"{key} limit below its request")
        args = self.container().get("args", [])
        if "--threads" in args:  # CPU-bound workers: more threads than CPUs only adds contention
            self.assertLessEqual(int(args[args.index("--threads") + 1]), quantity(resources["limits"]["cpu"]))

    def test_non_root(self):
        pod = self.one("Deployment")["spec"]["template"]["spec"]
        c = self.container()
        self.assertTrue(pod["securityContext"]["runAsNonRoot"])
        user = next(rest for kw, rest in self.runtime if kw == "USER").split(":")[0]
        self.assertNotIn(user, ("0", "root"))
        self.assertEqual(str(pod["securityContext"]["runAsUser"]), user, "runAsUser differs from the image's USER")
        self.assertFalse(c["securityContext"]["allowPrivilegeEscalation"])
        self.assertTrue(c["securityContext"]["readOnlyRootFilesystem"])
        self.assertIn("ALL", c["securityContext"]["capabilities"]["drop"])

    def test_graceful_termination(self):
        pod = self.one("Deployment")["spec"]["template"]["spec"]
        grace = pod["terminationGracePeriodSeconds"]
        pause = 0
        pre_stop = self.container().get("lifecycle", {}).get("preStop", {}).get("exec", {}).get("command", [])
        if pre_stop[:1] == ["sleep"]:
            pause = float(pre_stop[1])
        self.assertGreaterEqual(grace, pause + 10, "the grace period must cover the preStop pause and in-flight work")
        strategy = self.one("Deployment")["spec"]["strategy"]["rollingUpdate"]
        self.assertEqual(strategy["maxUnavailable"], 0)

    def test_selectors_match_pod_labels(self):
        deployment = self.one("Deployment")
        labels = deployment["spec"]["template"]["metadata"]["labels"]
        selectors = [deployment["spec"]["selector"]["matchLabels"], self.one("Service")["spec"]["selector"]]
        selectors += [p["spec"]["selector"]["matchLabels"] for p in self.by_kind.get("PodDisruptionBudget", [])]
        for selector in selectors:
            for key, value in selector.items():
                self.assertEqual(labels.get(key), value)

    def test_service_targets_the_container_port(self):
        for port in self.one("Service")["spec"]["ports"]:
            self.assertEqual(self.named_port(port["targetPort"]), 8080)

    def test_hpa(self):
        hpa = self.one("HorizontalPodAutoscaler")["spec"]
        deployment = self.one("Deployment")
        self.assertEqual(hpa["scaleTargetRef"]["kind"], "Deployment")
        self.assertEqual(hpa["scaleTargetRef"]["name"], deployment["metadata"]["name"])
        self.assertEqual(hpa["scaleTargetRef"]["apiVersion"], deployment["apiVersion"])
        self.assertGreaterEqual(hpa["minReplicas"], 2, "one replica is a single point of failure")
        self.assertGreaterEqual(hpa["maxReplicas"], hpa["minReplicas"])
        cpu = [m for m in hpa["metrics"] if m["type"] == "Resource" and m["resource"]["name"] == "cpu"]
        self.assertEqual(len(cpu), 1)
        self.assertEqual(cpu[0]["resource"]["target"]["type"], "Utilization")
        self.assertTrue(0 < cpu[0]["resource"]["target"]["averageUtilization"] <= 100)
        # Utilization is relative to the request: without a CPU request the HPA cannot scale.
        self.assertIn("cpu", self.container()["resources"]["requests"])

    def test_ingress_body_size_matches_the_service(self):
        for ingress in self.by_kind.get("Ingress", []):
            annotation = ingress["metadata"]["annotations"]["nginx.ingress.kubernetes.io/proxy-body-size"]
            args = self.container().get("args", [])
            self.assertIn("--max-body-mb", args, "set --max-body-mb explicitly so the ingress can match it")
            self.assertEqual(nginx_size_mib(annotation), int(args[args.index("--max-body-mb") + 1]))
            service = self.one("Service")
            service_ports = {p.get("name") for p in service["spec"]["ports"]} | {p["port"] for p in service["spec"]["ports"]}
            for rule in ingress["spec"]["rules"]:
                for path in rule["http"]["paths"]:
                    backend = path["backend"]["service"]
                    self.assertEqual(backend["name"], service["metadata"]["name"])
                    port = backend["port"].get("name", backend["port"].get("number"))
                    self.assertIn(port, service_ports)


def install_deps_packages():
    """The Debian packages scripts/install-deps.sh installs (its `packages=( ... )` list)."""
    text = read(os.path.join(ROOT, "scripts", "install-deps.sh"))
    body = re.search(r"^packages=\((.*?)^\)", text, re.M | re.S).group(1)
    return {word for line in body.splitlines() for word in line.split("#")[0].split()}


def dockerfile_build_packages():
    """The packages the Dockerfile's build and test stages (every stage but the runtime one) install with apt-get."""
    text = re.sub(r"\\\n", " ", read(os.path.join(ROOT, "Dockerfile")))
    stages = text.split("\nFROM ")[1:-1]
    packages = set()
    for stage in stages:
        for command in re.findall(r"apt-get install ([^&]*)", stage):
            packages |= {w for w in command.split() if not w.startswith("-")}
    return packages


class Container(unittest.TestCase):
    # Not in the image's build or test stage, on purpose: the benchmark peer (benchmarks are not built there), the
    # browser (the Chromium test runs on the host) and the formatter (checked on the host).
    NOT_IN_IMAGE = {"libmeshoptimizer-dev", "chromium", "clang-format"}

    def test_build_stage_installs_what_install_deps_does(self):
        missing = install_deps_packages() - self.NOT_IN_IMAGE - dockerfile_build_packages()
        self.assertFalse(missing, f"scripts/install-deps.sh installs {sorted(missing)} but no build or test stage of the Dockerfile does")

    def test_healthcheck_and_signals(self):
        runtime = dockerfile_runtime_stage()
        healthcheck = next(rest for kw, rest in runtime if kw == "HEALTHCHECK")
        self.assertIn('CMD ["surfaced", "healthcheck"]', healthcheck)
        entrypoint = json.loads(next(rest for kw, rest in runtime if kw == "ENTRYPOINT"))
        self.assertEqual(entrypoint[0], "surfaced", "exec form, so surfaced is PID 1 and receives SIGTERM itself")


class Parsers(unittest.TestCase):
    """The checks above are only as good as these conversions."""

    def test_quantity(self):
        self.assertEqual(quantity("500m"), 0.5)
        self.assertEqual(quantity("2"), 2)
        self.assertEqual(quantity(2), 2)
        self.assertEqual(quantity("1Gi"), 2**30)
        self.assertEqual(quantity("129e6"), 129e6)
        self.assertGreater(quantity("1Gi"), quantity("1G"))
        self.assertLess(quantity("4096Mi"), quantity("5Gi"))
        with self.assertRaises(ValueError):
            quantity("1 GB")

    def test_nginx_size(self):
        self.assertEqual(nginx_size_mib("64m"), 64)
        self.assertEqual(nginx_size_mib("1g"), 1024)
        self.assertEqual(nginx_size_mib("512k"), 0.5)
        with self.assertRaises(ValueError):
            nginx_size_mib("64MB")

    def test_package_lists_are_found(self):
        self.assertTrue({"cmake", "libdraco-dev", "libgtest-dev"} <= install_deps_packages())
        self.assertTrue({"cmake", "libdraco-dev", "nodejs"} <= dockerfile_build_packages())
        self.assertNotIn("libdraco7", dockerfile_build_packages(), "the runtime stage's packages are not the build's")

    def test_vendored_three_matches_the_pin(self):
        web = os.path.join(ROOT, "clients", "web")
        pinned = json.loads(read(os.path.join(web, "package.json")))["dependencies"]["three"]
        vendored = read(os.path.join(web, "vendor", "three", "VERSION")).strip()
        self.assertEqual(vendored, pinned, "clients/web/vendor is not the pinned three.js: run scripts/vendor-web.sh")
        # every module the client imports from vendor/ is there
        sources = read(os.path.join(web, "index.html")) + "".join(
            read(os.path.join(web, "js", name)) for name in sorted(os.listdir(os.path.join(web, "js"))))
        for path in set(re.findall(r"""["'](?:\.\.?/)*(vendor/[^"']+)["']""", sources)):
            self.assertTrue(os.path.exists(os.path.join(web, path)), f"clients/web/{path} is missing")

    def test_serve_flags_are_found(self):
        self.assertTrue({"--host", "--port", "--threads", "--max-body-mb"} <= serve_flags())


if __name__ == "__main__":
    unittest.main(verbosity=2)
