#: the version of the package
__version__ = "0.1.0"

#: the OpenAPI ``info.version`` of the surfaced API this client was made for (api/openapi.json)
API_VERSION = "0.1.0"
