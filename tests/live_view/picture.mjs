// The live view's picture for docs/live-view.md, made from nothing but the build: starts hapticd on the demo's
// session (the simulated ViSHaRD3 and its operator; DDS off, the live view on a free loopback port), lets Debian's
// chromium, headless, open the page the live view serves (tools/live_view/viewer.html), waits while it draws,
// saves a PNG through the DevTools protocol (with `ws`) and stops the server. The docs test runs it (docs/
// live-view.md, "# makes"): the picture must come out, at the committed picture's size.
// Usage: node tests/live_view/picture.mjs OUT.png [WAIT_S]    (hapticd: $HAPTICD_BIN_DIR, build/default/bin or PATH)
import { spawn } from "node:child_process";
import { existsSync, writeFileSync } from "node:fs";
import path from "node:path";
import { WebSocket } from "ws";

const [out, waitText] = process.argv.slice(2);
if (!out) {
  console.error("usage: node tests/live_view/picture.mjs OUT.png [WAIT_S]");
  process.exit(2);
}
const waitS = Number(waitText ?? "8");
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const binDir = process.env.HAPTICD_BIN_DIR ?? (existsSync("build/default/bin/hapticd") ? "build/default/bin" : "");
const hapticd = binDir ? path.join(binDir, "hapticd") : "hapticd";

// The session runs (real time) for longer than the picture takes; its log names the live view's address. The
// operator pushes the handle on a 0.4 Hz sine (4 N along x, 3 N along y), so the picture shows a motion.
const operator = "devices.vishard3.device.parameters.operator_force";
const server = spawn(hapticd, ["--config", "config/sessions/demo.yaml", "--set", "dds.enabled=false",
  "--set", `${operator}=sine`, "--set", `${operator}_n=[4,3,0]`, "--set", `${operator}_frequency_hz=0.4`,
  "--duration", String(waitS + 20), "--live-view", "0"], { stdio: ["ignore", "pipe", "pipe"] });
let log = "";
const url = await new Promise((resolve, reject) => {
  const timer = setTimeout(() => reject(new Error(`no live view address from hapticd in 20 s:\n${log}`)), 20000);
  const scan = (chunk) => {
    log += chunk;
    const found = log.match(/live view on (ws:\/\/[0-9.]+:[0-9]+)/);
    if (found) {
      clearTimeout(timer);
      resolve(found[1]);
    }
  };
  server.stdout.on("data", scan);
  server.stderr.on("data", scan);
  server.on("exit", (code) => reject(new Error(`hapticd exited (${code}) before its live view ran:\n${log}`)));
}).catch((e) => {
  console.error(`picture: ${e.message}`);
  server.kill("SIGINT");
  process.exit(1);
});

const port = 9300 + Math.floor(Math.random() * 500);
const chromium = spawn("chromium", ["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
  `--remote-debugging-port=${port}`, "--remote-debugging-address=127.0.0.1", "--window-size=1440,480",
  url.replace(/^ws:/, "http:") + "/"], { stdio: "ignore" });  // the page connects to its own server on load
let status = 0;
let chromiumError = null;  // chromium missing or not startable: said instead of waiting for a page
chromium.on("error", (e) => { chromiumError = e; });
try {
  let target;
  for (let i = 0; i < 50 && !target; ++i) {
    await sleep(200);
    try {
      target = (await (await fetch(`http://127.0.0.1:${port}/json`)).json()).find((t) => t.type === "page");
    } catch {}
    if (chromiumError) throw new Error(`chromium: ${chromiumError.message}`);
  }
  if (!target) throw new Error("chromium did not open the page in 10 s");
  await sleep(1000 * waitS);
  const ws = new WebSocket(target.webSocketDebuggerUrl);
  await new Promise((r) => ws.on("open", r));
  ws.send(JSON.stringify({ id: 1, method: "Page.captureScreenshot", params: { format: "png",
    captureBeyondViewport: true, clip: { x: 0, y: 0, width: 1440, height: 480, scale: 1 } } }));
  const reply = await new Promise((r) => ws.on("message", (m) => r(JSON.parse(m))));
  writeFileSync(out, Buffer.from(reply.result.data, "base64"));
  ws.close();
  console.log(`picture: ${out} (live view ${url})`);
} catch (e) {
  console.error(`picture: ${e.message}`);
  status = 1;
} finally {
  chromium.kill();
  server.kill("SIGINT");  // the server's safe stop
}
process.exit(status);
