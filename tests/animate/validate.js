// Runs the Khronos glTF validator on each .glb named on the command line and prints one
// JSON line per file: {"file", "errors", "warnings", "messages": [first errors]}.
const fs = require("fs");
const validator = require("gltf-validator");

(async () => {
  for (const file of process.argv.slice(2)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
      maxIssues: 50,
      format: "glb",
    });
    const messages = report.issues.messages
      .filter((m) => m.severity === 0)
      .map((m) => `${m.code} ${m.pointer || ""} ${m.message}`);
    console.log(JSON.stringify({
      file,
      errors: report.issues.numErrors,
      warnings: report.issues.numWarnings,
      messages,
    }));
  }
})().catch((e) => {
  console.error(e);
  process.exit(1);
});
