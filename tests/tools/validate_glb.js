// Runs the Khronos glTF validator (npm gltf-validator) on GLB files and prints each report's
// counts and its errors and warnings.
//   node validate_glb.js MODULE_DIR FILE.glb...
// MODULE_DIR holds node_modules/gltf-validator (npm install --prefix MODULE_DIR gltf-validator).
// Exit 0: no errors in any file; 1: errors (or a file that cannot be read); 77: the validator
// is not installed (ctest's SKIP_RETURN_CODE).
'use strict';

const fs = require('fs');
const path = require('path');

if (process.argv.length < 4) {
    console.error('usage: node validate_glb.js MODULE_DIR FILE.glb...');
    process.exit(2);
}
const moduleDir = process.argv[2];
let validator;
try {
    validator = require(path.resolve(moduleDir, 'node_modules', 'gltf-validator'));
} catch (e) {
    console.log(`SKIP: gltf-validator is not installed in ${moduleDir} (${e.code || e.message})`);
    process.exit(77);
}

async function validate(file) {
    const bytes = new Uint8Array(fs.readFileSync(file));
    // The surface has no external resources; refuse any, so that the report says so.
    const report = await validator.validateBytes(bytes, {
        maxIssues: 0,
        externalResourceFunction: (uri) => Promise.reject(new Error(`external resource ${uri}`)),
    });
    const issues = report.issues;
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
                `${issues.numInfos} infos, ${issues.numHints} hints (gltf-validator ` +
                `${report.validatorVersion})`);
    for (const m of issues.messages) {
        // severity: 0 error, 1 warning, 2 info, 3 hint
        const kind = ['error', 'warning', 'info', 'hint'][m.severity] || m.severity;
        console.log(`  ${kind} ${m.code}: ${m.message}${m.pointer ? ' at ' + m.pointer : ''}`);
    }
    return issues.numErrors;
}

(async () => {
    let errors = 0;
    for (const file of process.argv.slice(3)) {
        try {
            errors += await validate(file);
        } catch (e) {
            console.log(`${file}: ${e.message}`);
            errors += 1;
        }
    }
    process.exit(errors === 0 ? 0 : 1);
})();
