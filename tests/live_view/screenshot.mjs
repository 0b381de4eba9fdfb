// The live view's picture for docs/live-view.md: Debian's chromium, headless, opens the page a running session's
// live view serves (tools/live_view/viewer.html, at http://ADDRESS:PORT/), waits while it draws, and saves a PNG
// (through the DevTools protocol, with `ws`). Not a test. Usage: node screenshot.mjs LIVE_VIEW_URL OUT.png [WAIT_S]
import { spawn } from "node:child_process";
import { writeFileSync } from "node:fs";
import { WebSocket } from "ws";

const [url, out, waitText] = process.argv.slice(2);
const page = url.replace(/^ws:/, "http:") + "/";  // the page from the server's own origin
const port = 9300 + Math.floor(Math.random() * 500);
const chromium = spawn("chromium", ["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
  `--remote-debugging-port=${port}`, "--remote-debugging-address=127.0.0.1", "--window-size=1440,480",
  page], { stdio: "ignore" });
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
try {
  let target;
  for (let i = 0; i < 50 && !target; ++i) {
    await sleep(200);
    try {
      target = (await (await fetch(`http://127.0.0.1:${port}/json`)).json()).find((t) => t.type === "page");
    } catch {}
  }
  await sleep(1000 * Number(waitText ?? "8"));
  const ws = new WebSocket(target.webSocketDebuggerUrl);
  await new Promise((r) => ws.on("open", r));
  ws.send(JSON.stringify({ id: 1, method: "Page.captureScreenshot", params: { format: "png", captureBeyondViewport: true, clip: { x: 0, y: 0, width: 1440, height: 480, scale: 1 } } }));
  const reply = await new Promise((r) => ws.on("message", (m) => r(JSON.parse(m))));
  writeFileSync(out, Buffer.from(reply.result.data, "base64"));
  ws.close();
  console.log(`screenshot: ${out}`);
} finally {
  chromium.kill();
}
