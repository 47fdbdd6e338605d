// Issue 30: the Khronos glTF validator (npm gltf-validator) on each glb named: exit 1 on
// any error (warnings and infos are printed).
'use strict';
const fs = require('fs');
const validator = require('gltf-validator');
(async () => {
  let errors = 0;
  for (const file of process.argv.slice(2)) {
    const { issues } = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)));
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ${issues.numInfos} infos`);
    for (const m of issues.messages) console.log(`  ${['error', 'warning', 'info', 'hint'][m.severity]} ${m.code} ${m.pointer || ''}: ${m.message}`);
    errors += issues.numErrors;
  }
  process.exit(errors ? 1 : 0);
})();
