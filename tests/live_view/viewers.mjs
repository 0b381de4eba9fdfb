// Live-view viewers for measurements (scripts/measure-live-view.sh): N viewers subscribe to every channel of a
// hapticd live view; the first NEVER_READING of them stop reading their socket once subscribed (their TCP
// window fills, the server's queue for them fills, and it must drop or disconnect them). Runs DURATION_S and
// prints what each viewer got. Bounded by its own duration.
//
// Usage: node viewers.mjs URL N NEVER_READING DURATION_S
import foxglove from "@foxglove/ws-protocol";
import { WebSocket } from "ws";

const { FoxgloveClient } = foxglove;
const [url, countText, neverText, durationText] = process.argv.slice(2);
const count = Number(countText);
const neverReading = Number(neverText);
const durationMs = 1000 * Number(durationText);

const viewers = [];
for (let i = 0; i < count; ++i) {
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const v = { messages: 0, closed: false, subscribed: 0 };
  client.on("advertise", (channels) => {
    for (const c of channels) {
      client.subscribe(c.id);
      ++v.subscribed;
    }
    if (i < neverReading) setTimeout(() => ws._socket?.pause(), 200);  // reads nothing from here on
  });
  client.on("message", () => ++v.messages);
  client.on("close", () => (v.closed = true));
  client.on("error", () => {});
  viewers.push({ ws, client, v });
}
setTimeout(() => {
  viewers.forEach(({ v }, i) =>
    console.log(`viewer ${i}${i < neverReading ? " (never reading)" : ""}: ${v.subscribed} subscriptions, ` +
                `${v.messages} messages, ${v.closed ? "disconnected by the server" : "connected"}`));
  for (const { ws } of viewers) ws.terminate();
  process.exit(0);
}, durationMs);
