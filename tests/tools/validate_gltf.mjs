// Runs the Khronos glTF validator (npm gltf-validator) on one .glb/.gltf file.
// Output: first line "errors warnings infos hints" (easy to parse from C++ without a JSON library), then the
// validator's full JSON report. Exit code 0 when the validator ran (whatever it found), 2 when it could not.
// Usage: node tests/tools/validate_gltf.mjs FILE
import { readFile } from 'node:fs/promises';
import { createRequire } from 'node:module';

// Resolve the validator from tests/node_modules regardless of the caller's working directory.
const require = createRequire(new URL('../package.json', import.meta.url));

const file = process.argv[2];
if (!file) {
    console.error('usage: node validate_gltf.mjs FILE');
    process.exit(2);
}

try {
    const validator = require('gltf-validator');
    const bytes = new Uint8Array(await readFile(file));
    const report = await validator.validateBytes(bytes, {
        uri: file,
        maxIssues: 0,  // report everything: tests print the report on failure
        // A GLB from our writer is self-contained; an external reference is itself a finding, not a file to load.
        externalResourceFunction: (uri) => Promise.reject(new Error(`external resource not allowed: ${uri}`)),
    });
    const issues = report.issues;
    console.log(`${issues.numErrors} ${issues.numWarnings} ${issues.numInfos} ${issues.numHints}`);
    console.log(JSON.stringify(report, null, 2));
} catch (error) {
    console.error(`validator failed: ${error && error.stack ? error.stack : error}`);
    process.exit(2);
}
