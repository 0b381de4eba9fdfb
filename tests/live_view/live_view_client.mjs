// The live view's test client (tests/e2e/live_view_test.sh runs it against a hapticd serving a live view):
// Foxglove's own WebSocket protocol client connects, reads the server info and the channels, subscribes, and
// checks the messages' contents; beside it, what the server must refuse. Exits 0 when every check passed, 1 with
// the failures listed. Bounded: gives up after --timeout seconds.
//
// Usage: node live_view_client.mjs URL DEVICE LINK[,LINK...] DOF MAX_CLIENTS [TIMEOUT_S]
import foxglove from "@foxglove/ws-protocol";  // a CommonJS package: its exports through the default
import { WebSocket } from "ws";

const { FoxgloveClient } = foxglove;

const [url, device, linkList, dofText, maxClientsText, timeoutText] = process.argv.slice(2);
const dof = Number(dofText);
const links = linkList.split(",");
const maxClients = Number(maxClientsText);
const timeoutMs = 1000 * Number(timeoutText ?? "30");
const failures = [];
const check = (ok, what) => {
  if (!ok) failures.push(what);
};
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
const decoder = new TextDecoder();

setTimeout(() => {
  console.error(`live_view_client: timed out after ${timeoutMs / 1000} s; failures so far: ${failures.join("; ")}`);
  process.exit(1);
}, timeoutMs).unref();

// A connection without the Foxglove subprotocol is refused with an explanation.
async function refusedWithoutSubprotocol() {
  return new Promise((resolve) => {
    const ws = new WebSocket(url);
    ws.on("unexpected-response", (_req, res) => {
      let body = "";
      res.on("data", (chunk) => (body += chunk));
      res.on("end", () => resolve({ status: res.statusCode, body }));
    });
    ws.on("open", () => {
      ws.close();
      resolve({ status: 101, body: "" });
    });
    ws.on("error", () => {});
  });
}

function connect() {
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const seen = { serverInfo: null, channels: [], statuses: [], messages: new Map(), closed: false };
  client.on("serverInfo", (info) => (seen.serverInfo = info));
  client.on("advertise", (channels) => seen.channels.push(...channels));
  client.on("status", (s) => seen.statuses.push(s));
  client.on("close", () => (seen.closed = true));
  client.on("error", () => {});
  client.on("message", ({ subscriptionId, timestamp, data }) => {
    const list = seen.messages.get(subscriptionId) ?? [];
    list.push({ timestamp, value: JSON.parse(decoder.decode(data)) });
    seen.messages.set(subscriptionId, list);
  });
  return { ws, client, seen };
}

async function until(predicate, what) {
  while (!predicate()) {
    if (failures.length > 50) break;
    await sleep(20);
  }
  return what;
}

const finite = (v) => typeof v === "number" && Number.isFinite(v);
const finiteVector = (v) => v && finite(v.x) && finite(v.y) && finite(v.z);

async function main() {
  const refused = await refusedWithoutSubprotocol();
  check(refused.status === 400, `without the subprotocol: HTTP ${refused.status}, expected 400`);
  check(refused.body.includes("foxglove.websocket.v1"), "the refusal names the subprotocol");

  const { ws, client, seen } = connect();
  await until(() => seen.serverInfo && seen.channels.length > 0);
  check(seen.serverInfo.name.startsWith("hapticd"), `server name '${seen.serverInfo.name}'`);

  const byTopic = new Map(seen.channels.map((c) => [c.topic, c]));
  const expected = {
    [`/${device}/transforms`]: "foxglove.FrameTransforms",
    [`/${device}/scene`]: "foxglove.SceneUpdate",
    [`/${device}/state`]: "hapticd.DeviceState",
  };
  for (const [topic, schemaName] of Object.entries(expected)) {
    const c = byTopic.get(topic);
    check(c !== undefined, `channel ${topic} advertised`);
    if (!c) continue;
    check(c.encoding === "json", `${topic}: encoding ${c.encoding}`);
    check(c.schemaName === schemaName, `${topic}: schema ${c.schemaName}, expected ${schemaName}`);
    let schema = null;
    try {
      schema = JSON.parse(c.schema);
    } catch {
      check(false, `${topic}: its schema is not JSON`);
    }
    check(schema && schema.type === "object" && schema.title === schemaName, `${topic}: its schema's title`);
  }
  if (failures.length > 0) return;

  // A malformed request and one for a channel that does not exist: error statuses, the connection stays.
  ws.send('{"op":"subscribe","subscriptions":[{"id":"x"}]}');
  ws.send('{"op":"subscribe","subscriptions":[{"id":90,"channelId":9999}]}');
  await until(() => seen.statuses.length >= 2);
  check(seen.statuses.every((s) => s.level === 2), "malformed requests are answered with error statuses");
  check(seen.statuses.some((s) => s.message.includes("9999")), "the unknown channel is named");

  const sub = {};
  for (const topic of Object.keys(expected)) sub[topic] = client.subscribe(byTopic.get(topic).id);
  const wanted = 10;
  await until(() => Object.values(sub).every((id) => (seen.messages.get(id) ?? []).length >= wanted));

  // Frame transforms: every link of the robot model and the handle point, in the world frame.
  const transforms = seen.messages.get(sub[`/${device}/transforms`]);
  const last = transforms[transforms.length - 1].value.transforms;
  const children = new Set(last.map((t) => t.child_frame_id));
  for (const link of links) check(children.has(`${device}/${link}`), `transform of ${device}/${link}`);
  check(children.has(`${device}/handle_point`), "transform of the handle point");
  check(
    last.every((t) => t.parent_frame_id === "world" && finiteVector(t.translation) && finite(t.rotation.w)),
    "transforms in the world frame, finite"
  );

  // The state: joints, mode, and a handle that matches the transforms of the same instant.
  const states = seen.messages.get(sub[`/${device}/state`]);
  const state = states[states.length - 1].value;
  check(state.device === device, `state of ${state.device}`);
  check(state.mode === "running", `mode ${state.mode}`);
  check(Array.isArray(state.flags), "flags by name");
  for (const key of ["name", "position", "velocity", "torque"])
    check(state.joints[key].length === dof, `joints.${key}: ${state.joints[key].length} of ${dof}`);
  check(finiteVector(state.handle.position) && finiteVector(state.operator_wrench.force), "finite handle and wrench");
  let matched = false;
  for (const t of transforms) {
    const s = states.find((x) => x.timestamp === t.timestamp);
    if (!s) continue;
    const h = t.value.transforms.find((x) => x.child_frame_id === `${device}/handle_point`);
    const p = s.value.handle.position;
    matched = Math.hypot(h.translation.x - p.x, h.translation.y - p.y, h.translation.z - p.z) < 1e-12;
    break;
  }
  check(matched, "the handle point's transform and the state of the same instant agree");
  const cycles = states.map((s) => s.value.cycle);
  check(
    cycles.every((c, i) => i === 0 || c > cycles[i - 1]),
    "states in order, each newer than the last"
  );
  check(
    states.every((s, i) => i === 0 || s.timestamp > states[i - 1].timestamp),
    "message times increase"
  );

  // The scene: links, markers and the two wrench arrows as entities in the world frame.
  const scenes = seen.messages.get(sub[`/${device}/scene`]);
  const entities = new Map(scenes[scenes.length - 1].value.entities.map((e) => [e.id, e]));
  for (const id of ["links", "markers", "operator_wrench", "rendered_wrench"])
    check(entities.has(`${device}/${id}`), `scene entity ${device}/${id}`);
  check(entities.get(`${device}/links`)?.cylinders.length >= links.length - 1, "a cylinder per link");
  check(entities.get(`${device}/markers`)?.spheres.length >= 2, "handle and target markers");

  // Unsubscribed: the state channel falls silent, the others go on.
  client.unsubscribe(sub[`/${device}/state`]);
  await sleep(300);
  const stateCount = seen.messages.get(sub[`/${device}/state`]).length;
  const transformCount = seen.messages.get(sub[`/${device}/transforms`]).length;
  await sleep(600);
  check(seen.messages.get(sub[`/${device}/state`]).length === stateCount, "no state after unsubscribing");
  check(seen.messages.get(sub[`/${device}/transforms`]).length > transformCount, "transforms go on");

  // At most MAX_CLIENTS viewers: the next is refused.
  const others = [];
  for (let i = 1; i < maxClients; ++i) others.push(connect());
  await until(() => others.every((o) => o.seen.serverInfo));
  const extra = connect();
  await until(() => extra.seen.closed || extra.seen.serverInfo);
  check(extra.seen.closed && !extra.seen.serverInfo, `viewer ${maxClients + 1} refused`);
  for (const o of others) o.client.close();
  client.close();

  const total = [...seen.messages.values()].reduce((n, l) => n + l.length, 0);
  console.log(
    `live_view_client: ${seen.channels.length} channels, ${total} messages, ${links.length} links; ` +
      `${failures.length} failure(s)`
  );
}

main()
  .catch((e) => failures.push(`exception: ${e.stack ?? e}`))
  .finally(() => {
    for (const f of failures) console.error(`FAIL: ${f}`);
    process.exit(failures.length === 0 ? 0 : 1);
  });
