// Validates an OpenAPI document (3.0 or 3.1) against the official JSON schema.
// Usage: node validate_openapi.mjs FILE   -> prints {"valid": true} or {"valid": false, "errors": [...]}; exit 0/1
import { readFileSync } from "node:fs";
import { Validator } from "@seriousme/openapi-schema-validator";

const file = process.argv[2];
const validator = new Validator();
const result = await validator.validate(JSON.parse(readFileSync(file, "utf8")));
console.log(JSON.stringify({ valid: result.valid, version: validator.version, errors: result.errors ?? [] }));
process.exit(result.valid ? 0 : 1);
