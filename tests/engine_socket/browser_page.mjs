// A page the engine socket serves (tools/engine_socket/wall.html, scene.html) in Debian's chromium, headless: opens
// PAGE_URL, clicks its button `claim` as a person would (a trusted mouse event through the DevTools protocol) until
// window[VAR].claimed, lets it run RUN_S seconds, then reads the page's window[VAR] through the DevTools protocol
// (with `ws`) and prints it as JSON on one line. The tests check what it says (tests/e2e/engine_socket_test.sh,
// scene_browser_test.sh).
//   node browser_page.mjs PAGE_URL VAR RUN_S [CLAIMED_FILE | --look]
// CLAIMED_FILE: written once the page has claimed (the test then has the operator push); --look: no click, the page
// only looks for RUN_S seconds.
import { spawn } from "node:child_process";
import { writeFileSync } from "node:fs";
import { createRequire } from "node:module";
const require = createRequire(new URL("../live_view/package.json", import.meta.url));
const WebSocket = require("ws");

const [page, variable, runS, claimedFile] = process.argv.slice(2);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const claimed = `window.${variable} && window.${variable}.claimed`;
const port = 9800 + Math.floor(Math.random() * 150);
const chromium = spawn("chromium", ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-timer-throttling",
  "--disable-renderer-backgrounding", `--remote-debugging-port=${port}`, "--remote-debugging-address=127.0.0.1",
  page], { stdio: "ignore" });
let chromiumError = null;
chromium.on("error", (e) => { chromiumError = e; });
let status = 0;
try {
  let target;
  for (let i = 0; i < 75 && !target; ++i) {
    await sleep(200);
    try {
      target = (await (await fetch(`http://127.0.0.1:${port}/json`)).json()).find((t) => t.type === "page");
    } catch {}
    if (chromiumError) throw new Error(`chromium: ${chromiumError.message}`);
  }
  if (!target) throw new Error("chromium did not open the page in 15 s");
  const dev = new WebSocket(target.webSocketDebuggerUrl);
  await new Promise((r, j) => { dev.on("open", r); dev.on("error", j); });
  let id = 0;
  const call = (method, params) => new Promise((resolve) => {
    const mine = ++id;
    const listener = (m) => {
      const reply = JSON.parse(m);
      if (reply.id !== mine) return;
      dev.off("message", listener);
      resolve(reply.result);
    };
    dev.on("message", listener);
    dev.send(JSON.stringify({ id: mine, method, params }));
  });
  const evaluate = async (expression) => {
    const r = await call("Runtime.evaluate", { expression, returnByValue: true });
    return r && r.result ? r.result.value : undefined;
  };
  // The page claims only on a person's click: a real (trusted) mouse click on its Claim button, as a person's.
  const where = `(() => { const b = document.getElementById("claim"); if (!b || b.disabled) return null;
    b.scrollIntoView({ block: "center" }); const r = b.getBoundingClientRect(); return { x: r.x + r.width / 2, y: r.y + r.height / 2 }; })()`;
  // Clicked again until the page has claimed (a click before the page's first paint hits nothing; a slow server -
  // ThreadSanitizer's - answers late), at most 20 times in 10 s.
  let button = null;
  const look = claimedFile === "--look";
  for (let i = 0; i < 100 && !look && !(button = await evaluate(where)); ++i) await sleep(100);
  if (!button && !look) throw new Error("the page's Claim button did not become active");
  for (let click = 0; click < 20 && !look && !(await evaluate(claimed)); ++click) {
    button = (await evaluate(where)) || button;
    for (const type of ["mousePressed", "mouseReleased"])
      await call("Input.dispatchMouseEvent", { type, x: button.x, y: button.y, button: "left", clickCount: 1 });
    for (let i = 0; i < 5 && !(await evaluate(claimed)); ++i) await sleep(100);
  }
  if (claimedFile && !look) writeFileSync(claimedFile, "claimed\n");
  await sleep(1000 * Number(runS));
  console.log(JSON.stringify(await evaluate(`window.${variable}`)));
  dev.close();
} catch (e) {
  console.error(`browser page: ${e.message}`);
  status = 1;
} finally {
  chromium.kill();
}
process.exit(status);
