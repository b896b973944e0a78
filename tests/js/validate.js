#!/usr/bin/env node
// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Runs the Khronos glTF-Validator on one .gltf or .glb file.
//   node tests/js/validate.js FILE [--json]
// Prints one line per issue ("[E|W|I|H] CODE POINTER MESSAGE") or, with --json, the whole report
// (deterministic: no timestamp, no issue limit). Exit status: 0 = no errors, 1 = errors,
// 2 = the validator could not run (missing file, unknown format, bad arguments).
'use strict';

const fs = require('fs');
const path = require('path');

function main() {
  const args = process.argv.slice(2);
  const json = args.includes('--json');
  const files = args.filter((a) => a !== '--json');
  if (files.length !== 1) {
    console.error('usage: node validate.js FILE [--json]');
    process.exit(2);
  }
  const file = files[0];
  let validator;
  try {
    validator = require('gltf-validator');
  } catch (e) {
    console.error('validate.js: gltf-validator is not installed (run scripts/setup_js.sh)');
    process.exit(2);
  }
  let bytes;
  try {
    bytes = new Uint8Array(fs.readFileSync(file));
  } catch (e) {
    console.error(`validate.js: cannot read ${file}: ${e.message}`);
    process.exit(2);
  }
  validator
      .validateBytes(bytes, {
        uri: path.basename(file),
        maxIssues: 0,            // unlimited
        writeTimestamp: false,   // deterministic report
        externalResourceFunction: (uri) =>
            fs.promises.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)))
                .then((b) => new Uint8Array(b)),
      })
      .then(
          (report) => {
            if (json) {
              process.stdout.write(JSON.stringify(report, null, 2) + '\n');
            } else {
              for (const m of report.issues.messages) {
                console.log(`[${'EWIH'[m.severity]}] ${m.code} ${m.pointer ?? ''} ${m.message}`);
              }
            }
            process.exitCode = report.issues.numErrors > 0 ? 1 : 0;
          },
          (e) => {
            console.error(`validate.js: ${file}: ${e && e.message ? e.message : e}`);
            process.exitCode = 2;
          });
}

main();
