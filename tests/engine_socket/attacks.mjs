// The engine socket under attack (tests/e2e/engine_socket_test.sh), with real clients that read their replies:
// an intruder that claims a claimed device, commands it, claims under the owner's client id, sends malformed
// messages and floods; a client that never reads; and the owner leaving, which frees the device.
//   node attacks.mjs URL DEVICE
// Prints "ok: ..." per check; exits 1 at the first that fails.
import { createRequire } from 'module';
const require = createRequire(new URL('../live_view/package.json', import.meta.url));
const WebSocket = require('ws');

const [url, device] = process.argv.slice(2, 4);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const clients = [];
function fail(why) {
  console.log(`FAIL: ${why}`);
  for (const c of clients) console.log(`  ${c.name} was told: ${JSON.stringify([...c.errors.values()])}`);
  process.exit(1);
}
setTimeout(() => fail('the attacks took longer than 40 s'), 40000).unref();

// A client that keeps what it is told: replies by id, errors by code, the newest state.
function connect(name) {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(url);
    const c = { name, ws, replies: new Map(), errors: new Map(), state: null, inventory: null, closed: false, id: 0 };
    clients.push(c);
    ws.on('message', (data) => {
      const m = JSON.parse(data.toString());
      if (m.session_id !== undefined) { c.inventory = m; resolve(c); }
      else if (m.reply) c.replies.set(m.reply.id, m.reply);
      else if (m.error) c.errors.set(m.error.code, m.error);
      else if (m.devices) c.state = m.devices[0];
    });
    ws.on('close', () => { c.closed = true; });
    ws.on('error', reject);
    ws.on('open', () => ws.send(JSON.stringify({ session: { configure: { profile: { name } } } })));
  });
}
async function request(c, kind) {
  const id = ++c.id;
  c.ws.send(JSON.stringify({ request: { id, kind, device } }));
  for (let i = 0; i < 100 && !c.replies.has(id); ++i) await sleep(20);
  if (!c.replies.has(id)) fail(`no reply to ${kind}`);
  return c.replies.get(id);
}
async function error(c, code) {
  for (let i = 0; i < 100 && !c.errors.has(code); ++i) await sleep(20);
  return c.errors.get(code);
}
const coupling = (c) => JSON.stringify({ devices: [{ device_id: device, commands: { set_coupling: {
  position: c.state.state.cursor_position } } }] });

const owner = await connect('owner');
if (!(await request(owner, 'claim')).accepted) fail('the owner could not claim');
console.log('ok: the owner claimed');

const intruder = await connect('intruder');
const refused = await request(intruder, 'claim');
if (refused.accepted || !refused.message.includes("claimed by 'owner'")) fail(`a second claim: ${JSON.stringify(refused)}`);
console.log(`ok: the intruder's claim is refused: ${refused.message}`);

while (!intruder.state) await sleep(10);
for (let i = 0; i < 50; ++i) intruder.ws.send(coupling(intruder));
const notOwner = await error(intruder, 'not_owner');
if (!notOwner) fail("the intruder's commands were not rejected as not_owner");
console.log(`ok: the intruder's commands are rejected: ${notOwner.message}`);

intruder.ws.send('{"devices": [ not json');
intruder.ws.send(JSON.stringify({ devices: [{ device_id: device, commands: { set_coupling: { position: { x: 'far' } } } }] }));
const malformed = await error(intruder, 'malformed');
if (!malformed || malformed.count < 1) fail('malformed messages were not refused');
console.log(`ok: malformed messages are refused: ${malformed.message}`);

const spoof = await connect('owner');  // the owner's client id from another connection
const spoofed = await request(spoof, 'release');
if (spoofed.accepted) fail("another connection under the owner's id released the device");
while (!spoof.state) await sleep(10);
for (let i = 0; i < 20; ++i) spoof.ws.send(coupling(spoof));
if (!(await error(spoof, 'not_owner'))) fail("commands under the owner's id from another connection were taken");
console.log("ok: the owner's client id from another connection neither releases nor commands the device");
spoof.ws.close();

for (let i = 0; i < 30000; ++i) intruder.ws.send('{}');
const limited = await error(intruder, 'rate_limited');
if (!limited) fail('a flood of 30000 messages was not rate limited');
console.log(`ok: a flood is rate limited: ${limited.message}`);

const deaf = await connect('deaf');  // reads nothing from here on: the states pile up
deaf.ws._socket.pause();
await sleep(3000);
deaf.ws._socket.resume();
for (let i = 0; i < 100 && !deaf.closed; ++i) await sleep(20);
if (!deaf.closed) fail('a client that read nothing for 3 s is still connected');
console.log('ok: a client that reads nothing is disconnected');

if (owner.state.status.owner !== 'owner') fail(`the owner lost the device meanwhile: ${owner.state.status.owner}`);
owner.ws.close();
await sleep(300);
const taken = await request(intruder, 'claim');
if (!taken.accepted) fail(`the device was not freed when its owner left: ${taken.message}`);
console.log('ok: the owner left, its claim ended, another client claimed the device');
await request(intruder, 'release');
intruder.ws.close();
console.log('7 passed, 0 failed');
process.exit(0);
