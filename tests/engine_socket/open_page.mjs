// Opens PAGE_URL in Debian's chromium, headless, for RUN_S seconds and nothing else (no click, no script): what a
// person's browser does when some site sends it to a page. The engine socket test's framing attack (an attacker's
// page that frames the socket's wall page) and its check that the wall page claims nothing on its own.
//   node open_page.mjs PAGE_URL RUN_S
import { spawn } from "node:child_process";

const [page, runS] = process.argv.slice(2);
const chromium = spawn("chromium", ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-timer-throttling",
  "--disable-renderer-backgrounding", "--remote-debugging-port=0", page], { stdio: "ignore" });
let failed = null;
chromium.on("error", (e) => { failed = e; });
await new Promise((r) => setTimeout(r, 1000 * Number(runS)));
chromium.kill();
if (failed) {
  console.error(`chromium: ${failed.message}`);
  process.exit(1);
}
console.log(`chromium had ${page} open for ${runS} s`);
