#!/usr/bin/env python3
"""Fails when a script client disagrees with api/openapi.json.

For every operation of the OpenAPI document (paths x methods):
  - the Python client (clients/python/surfaced) has a method named after its operationId in snake_case, the JS client
    (clients/js/surfaced.d.ts and surfaced.mjs) one named after the operationId itself;
  - the operation's options are its parameters (query and path; a header parameter under the client's name from
    HEADER_NAMES) and the top-level properties of its JSON request body. Each is a keyword of the Python method and a
    property of the JS method's options type (or a positional parameter), and neither client accepts a name the API
    does not document, except the transport arguments in CLIENT_ONLY (file bytes and their media type); a name the
    API marks deprecated (an old name it still accepts) need not be offered;
  - Python options other than the request's payload are keyword-only, take no **kwargs, and a default in the
    signature is the API's documented default (an option the API gives one default for must show it); a JS property's
    `@default` tag, where there is one, is the API's default;
  - no client has an endpoint method the API does not document.
Also: surfaced.API_VERSION and the JS API_VERSION are the document's info.version, and the JS package.json's exports
and types name files that exist.

    python3 tests/clients/client_drift_test.py [REPO_ROOT]
"""
import inspect
import json
import os
import re
import shutil
import subprocess
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", ".."))

#: header parameters of the API and the option name both clients give them
HEADER_NAMES = {"If-None-Match": "etag"}
#: arguments of the clients that are no API option: an upload's bytes (or BEZ text) and their media type
CLIENT_ONLY = {"python": {"data", "content_type", "bez"}, "js": {"data", "contentType", "bez"}}
#: the request's payload may be passed positionally in Python
PYTHON_POSITIONAL = {"mesh", "patches", "points", "scene", "bounds", "name", "surface"}
#: options whose Python default is None on purpose although the API documents a default
PYTHON_NONE_DEFAULT = {
    ("pointcloud", "normals"): "a list is the JSON input's normals, a bool the output option (query default true)",
    ("reconstruct", "normals"): "a list is the JSON input's normals, a bool the output option (query default true)",
}
#: client methods that are no endpoint
PYTHON_HELPERS = {"request", "server_version", "check_server_version"}
JS_HELPERS = {"request", "serverVersion", "checkServerVersion", "operation"}

problems = []


def problem(text):
    problems.append(text)


def snake(name):
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


# -- the API ---------------------------------------------------------------------------------------------------------
with open(os.path.join(ROOT, "api", "openapi.json")) as f:
    doc = json.load(f)
schemas = doc.get("components", {}).get("schemas", {})


def resolve(schema):
    seen = 0
    while isinstance(schema, dict) and "$ref" in schema:
        schema = schemas[schema["$ref"].rsplit("/", 1)[-1]]
        seen += 1
        if seen > 50:
            raise RuntimeError("$ref cycle")
    return schema


def properties(schema):
    """Top-level properties of a request schema, through $ref, allOf, oneOf and anyOf."""
    schema = resolve(schema)
    out = dict(schema.get("properties", {}))
    for key in ("allOf", "oneOf", "anyOf"):
        for branch in schema.get(key, []):
            out.update(properties(branch))
    return out


def default_of(schema):
    schema = resolve(schema)
    return schema.get("default", ...)


operations = []   # (operationId, {option: [documented defaults]})
deprecated = set()   # (operationId, name): deprecated names the API still accepts; a client need not offer them
path_params = set()   # (operationId, name)
for path, item in doc["paths"].items():
    for method, op in item.items():
        if method not in ("get", "put", "post", "delete", "patch", "head", "options"):
            continue
        op_id = op.get("operationId")
        if not op_id:
            problem(f"{method.upper()} {path}: no operationId")
            continue
        options = {}
        for param in item.get("parameters", []) + op.get("parameters", []):
            param = resolve(param)
            name = param["name"]
            if param.get("deprecated"):
                deprecated.add((op_id, name))
            if param["in"] == "header":
                if name not in HEADER_NAMES:
                    problem(f"{op_id}: header parameter {name} has no client name in HEADER_NAMES")
                    continue
                name = HEADER_NAMES[name]
            elif param["in"] == "cookie":
                continue
            options.setdefault(name, [])
            if param["in"] == "path":
                path_params.add((op_id, name))
                continue   # required by nature; a client may default it (patch_sample's "teapot")
            d = default_of(param.get("schema", {}))
            if d is not ...:
                options[name].append(d)
        content = op.get("requestBody", {}).get("content", {})
        if "application/json" in content:
            for name, schema in properties(content["application/json"].get("schema", {})).items():
                if resolve(schema).get("deprecated"):
                    deprecated.add((op_id, name))
                options.setdefault(name, [])
                d = default_of(schema)
                if d is not ...:
                    options[name].append(d)
        operations.append((op_id, options))


def same(a, b):
    return isinstance(a, bool) == isinstance(b, bool) and a == b


# -- Python ----------------------------------------------------------------------------------------------------------
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))
import surfaced  # noqa: E402

if surfaced.API_VERSION != doc["info"]["version"]:
    problem(f"python: surfaced.API_VERSION {surfaced.API_VERSION} is not the API's info.version "
            f"{doc['info']['version']}")

for op_id, options in operations:
    name = snake(op_id)
    method = getattr(surfaced.Client, name, None)
    if method is None:
        problem(f"python: no method Client.{name} for operation {op_id}")
        continue
    params = [p for p in inspect.signature(method).parameters.values() if p.name != "self"]
    for p in params:
        if p.kind is inspect.Parameter.VAR_KEYWORD:
            problem(f"python: Client.{name} takes **{p.name}: it would accept options the API does not document")
        elif p.kind is inspect.Parameter.VAR_POSITIONAL:
            problem(f"python: Client.{name} takes *{p.name}")
        elif p.kind is not inspect.Parameter.KEYWORD_ONLY and p.name not in PYTHON_POSITIONAL:
            problem(f"python: Client.{name}({p.name}) is not keyword-only")
    names = {p.name for p in params} - CLIENT_ONLY["python"]
    for missing in sorted(set(options) - names):
        if (op_id, missing) not in deprecated:
            problem(f"python: Client.{name} lacks the API's option {missing}")
    for extra in sorted(names - set(options)):
        problem(f"python: Client.{name} accepts {extra}, which the API does not document for {op_id}")
    for p in params:
        if p.name not in options:
            continue
        documented = options[p.name]
        if p.default is inspect.Parameter.empty or (op_id, p.name) in path_params:
            continue   # a required payload (scene, bounds), or a path parameter
        if p.default is not None:
            if not documented or not all(same(p.default, d) for d in documented):
                problem(f"python: Client.{name}({p.name}={p.default!r}): the API's default is "
                        + (" / ".join(repr(d) for d in documented) if documented else "not documented (use None)"))
        elif documented and (op_id, p.name) not in PYTHON_NONE_DEFAULT and (name, p.name) not in PYTHON_NONE_DEFAULT:
            problem(f"python: Client.{name}({p.name}=None): the signature should show the API's default "
                    f"{documented[0]!r}")

api_methods = {snake(op_id) for op_id, _ in operations}
for attr, value in vars(surfaced.Client).items():
    if callable(value) and not attr.startswith("_") and attr not in PYTHON_HELPERS and attr not in api_methods:
        problem(f"python: Client.{attr} is no operation of the API")


# -- JS: the declarations --------------------------------------------------------------------------------------------
js_dir = os.path.join(ROOT, "clients", "js")
with open(os.path.join(js_dir, "surfaced.d.ts")) as f:
    dts = f.read()
dts_code = re.sub(r"//[^\n]*", "", dts)


def block_after(text, start):
    """The text between the brace at or after start and its partner."""
    i = text.index("{", start)
    depth = 0
    for j in range(i, len(text)):
        if text[j] == "{":
            depth += 1
        elif text[j] == "}":
            depth -= 1
            if depth == 0:
                return text[i + 1:j]
    raise ValueError("unbalanced braces")


def top_level_lines(body):
    """Lines of a block at its own depth (members of nested object types and comments left out)."""
    depth, out, line = 0, [], ""
    body = re.sub(r"/\*.*?\*/", lambda m: m.group(0) if "@default" in m.group(0) else " ", body, flags=re.S)
    for ch in body:
        if ch in "{(<[":
            depth += 1
        elif ch in "})>]":
            depth -= 1
        if depth == 0 and ch in ";\n":
            out.append(line)
            line = ""
        elif depth == 0 or ch not in "\n":
            line += ch
    out.append(line)
    return out


interfaces = {}
for m in re.finditer(r"export\s+interface\s+(\w+)\s*(?:<[^{]*?>)?\s*(?:extends\s+([^{]+?))?\s*\{", dts_code):
    body = block_after(dts_code, m.end() - 1)
    bases = [re.sub(r"<.*", "", b).strip() for b in re.split(r",(?![^<]*>)", m.group(2) or "") if b.strip()]
    props, pending_default = {}, ...
    for line in top_level_lines(body):
        tag = re.search(r"@default\s+(.+?)\s*\*/", line)
        if tag:
            pending_default = tag.group(1)
        pm = re.match(r"\s*(?:/\*.*?\*/\s*)?(?:readonly\s+)?([A-Za-z_$][\w$]*)\??\s*:", line, re.S)
        if pm:
            props[pm.group(1)] = pending_default
            pending_default = ...
    interfaces[m.group(1)] = (bases, props)


def interface_props(name, seen=()):
    if name not in interfaces:
        problem(f"js: surfaced.d.ts has no interface {name}")
        return {}
    bases, props = interfaces[name]
    out = {}
    for base in bases:
        if base not in seen:
            out.update(interface_props(base, seen + (name,)))
    out.update(props)
    return out


client_match = re.search(r"export\s+declare\s+class\s+Client\s*\{", dts_code)
js_methods = {}
if not client_match:
    problem("js: surfaced.d.ts declares no class Client")
else:
    for line in top_level_lines(block_after(dts_code, client_match.end() - 1)):
        mm = re.match(r"\s*([A-Za-z_$][\w$]*)\s*\((.*?)\)\s*:", line, re.S)
        if mm and mm.group(1) != "constructor":
            js_methods[mm.group(1)] = [p.strip() for p in re.split(r",(?![^<{]*[>}])", mm.group(2)) if p.strip()]

js_api_version = re.search(r"export\s+const\s+API_VERSION\s*=\s*['\"]([^'\"]+)['\"]",
                           open(os.path.join(js_dir, "surfaced.mjs")).read())
if not js_api_version or js_api_version.group(1) != doc["info"]["version"]:
    problem(f"js: API_VERSION in surfaced.mjs ({js_api_version and js_api_version.group(1)}) is not the API's "
            f"info.version {doc['info']['version']}")


def parse_default(text):
    try:
        return json.loads(text.replace("'", '"'))
    except ValueError:
        return text


for op_id, options in operations:
    if op_id not in js_methods:
        problem(f"js: surfaced.d.ts declares no Client.{op_id} for operation {op_id}")
        continue
    names, defaults = set(), {}
    for param in js_methods[op_id]:
        pm = re.match(r"([A-Za-z_$][\w$]*)\??\s*:\s*(.+)", param, re.S)
        if not pm:
            problem(f"js: Client.{op_id}: cannot read the parameter {param!r}")
            continue
        type_name = pm.group(2).strip()
        if re.fullmatch(r"\w+Options", type_name):
            props = interface_props(type_name)
            names |= set(props)
            defaults.update({k: v for k, v in props.items() if v is not ...})
        else:
            names.add(pm.group(1))
    names -= CLIENT_ONLY["js"]
    for missing in sorted(set(options) - names):
        if (op_id, missing) not in deprecated:
            problem(f"js: Client.{op_id}'s options lack the API's option {missing}")
    for extra in sorted(names - set(options)):
        problem(f"js: Client.{op_id}'s options have {extra}, which the API does not document for {op_id}")
    for key, text in defaults.items():
        if key in options and not (options[key] and all(same(parse_default(text), d) for d in options[key])):
            problem(f"js: Client.{op_id}: {key} @default {text}, the API's default is "
                    + (" / ".join(repr(d) for d in options[key]) if options[key] else "not documented"))

for name in js_methods:
    if name not in {op_id for op_id, _ in operations} and name not in JS_HELPERS:
        problem(f"js: Client.{name} (surfaced.d.ts) is no operation of the API")

# the module itself has every declared method (when node is here to load it)
node = shutil.which("node")
if node:
    script = ("import(process.argv[1]).then((m) => console.log(JSON.stringify("
              "Object.getOwnPropertyNames(m.Client.prototype))))")
    result = subprocess.run([node, "-e", script, os.path.join(js_dir, "surfaced.mjs")], capture_output=True,
                            text=True, timeout=60)
    if result.returncode != 0:
        problem(f"js: surfaced.mjs does not load: {result.stderr.strip()}")
    else:
        implemented = set(json.loads(result.stdout))
        for name in sorted(set(js_methods) - implemented):
            problem(f"js: surfaced.d.ts declares Client.{name}, surfaced.mjs has no such method")
else:
    print("note: node not found; surfaced.mjs's methods not checked against surfaced.d.ts")

with open(os.path.join(js_dir, "package.json")) as f:
    package = json.load(f)
entry = package.get("exports", {}).get(".", {})
for label, target in (("types", package.get("types")), ("exports types", entry.get("types")),
                      ("exports default", entry.get("default"))):
    if not target or not os.path.isfile(os.path.join(js_dir, target)):
        problem(f"js: package.json {label} names {target!r}, which is not a file")

for text in problems:
    print("DRIFT " + text)
checked = len(operations)
if problems:
    print(f"{len(problems)} disagreements between the clients and api/openapi.json ({checked} operations)")
    sys.exit(1)
print(f"ok: {checked} operations; the Python and JS clients' methods and options match api/openapi.json")
