// A rendering engine in Node on hapticd's engine socket (WebSocket/JSON, docs/engine-socket.md): a wall normal to
// x, 2 cm ahead of where the handle starts, rendered through the server's virtual coupling - each state is answered
// with the proxy (the handle's pose, held back at the wall). The test client of tests/e2e/engine_socket_test.sh.
//   node wall_engine.mjs URL DEVICE DURATION_S [TOKEN]
// Prints "claimed 'DEVICE'", and at the end the states answered and where the handle came to rest. A claim that
// ends (the server says so in the state's owner) is taken again.
import { createRequire } from 'module';
const require = createRequire(new URL('../live_view/package.json', import.meta.url));
const WebSocket = require('ws');

const [url, device, duration] = process.argv.slice(2, 5);
const token = process.argv[5];
const ws = new WebSocket(token ? `${url}/?token=${token}` : url);
let startX = null, wallX = null, claimed = false, owned = false, answered = 0, lastX = 0, requestId = 0;
let claiming = false;
const client = 'node-wall-engine';

function claim() {
  claiming = true;
  ws.send(JSON.stringify({ request: { id: ++requestId, kind: 'claim', device } }));
}

ws.on('open', () => {
  ws.send(JSON.stringify({ session: { configure: { profile: { name: client } } }, subscribe: [device] }));
});
ws.on('message', (data) => {
  const m = JSON.parse(data.toString());
  if (m.session_id !== undefined) {
    if (!m.devices.some((d) => d.device_id === device)) {
      console.error(`no device '${device}' in the inventory`);
      process.exit(2);
    }
    return;
  }
  if (m.reply) {
    claiming = false;
    if (!m.reply.accepted) {
      console.error(`cannot claim '${device}': ${m.reply.message}`);
      process.exit(3);
    }
    console.log(claimed ? `claimed '${device}' again` : `claimed '${device}'; a wall 2 cm ahead`);
    claimed = true;
    return;
  }
  if (m.error) {
    console.log(`error ${m.error.code}: ${m.error.message}`);
    return;
  }
  const entry = m.devices && m.devices[0];
  if (!entry || entry.device_id !== device) return;
  const s = entry.state;
  if (startX === null) {
    startX = s.cursor_position.x;
    wallX = startX + 0.02;
    claim();
    return;
  }
  lastX = s.cursor_position.x;
  if (claimed && entry.status.owner === client) owned = true;  // the states say so from here on
  if (owned && entry.status.owner !== client && !claiming) {
    console.log(`the server ended the claim of '${device}'`);
    owned = false;
    claim();
    return;
  }
  if (!claimed) return;
  const position = { ...s.cursor_position, x: Math.min(s.cursor_position.x, wallX) };
  ws.send(JSON.stringify({
    devices: [{ device_id: device, state_serial: s.serial,
                commands: { set_coupling: { position, orientation: s.orientation } } }],
  }));
  ++answered;
});
ws.on('error', (e) => { console.error(`engine socket: ${e.message}`); process.exit(4); });
setTimeout(() => {
  console.log(`answered ${answered} states; handle ${(lastX - startX).toFixed(4)} m past the start, the wall at 0.0200 m`);
  ws.close();
  process.exit(0);
}, Number(duration) * 1000);
