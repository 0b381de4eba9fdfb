// The engines' worlds in the live view (tests/e2e/mujoco_engine_test.sh runs it against a hapticd with a live view
// and hapticd-mujoco-engine publishing its world): Foxglove's own protocol client subscribes to /world/scene and
// waits for the engine's entity ("world/ENGINE") with at least CUBES cubes and SPHERES spheres; then, with --gone,
// for its deletion once the engine has ended. Exits 0 when seen, 1 with what was seen otherwise. Bounded by
// TIMEOUT_S.
//
// Usage: node world_client.mjs URL ENGINE CUBES SPHERES TIMEOUT_S [--gone]
import foxglove from "@foxglove/ws-protocol";  // a CommonJS package: its exports through the default
import { WebSocket } from "ws";

const { FoxgloveClient } = foxglove;
const [url, engine, cubesText, spheresText, timeoutText, gone] = process.argv.slice(2);
const id = `world/${engine}`;
const decoder = new TextDecoder();
let last = "nothing";
setTimeout(() => {
  console.error(`world_client: timed out after ${timeoutText} s; last seen: ${last}`);
  process.exit(1);
}, 1000 * Number(timeoutText)).unref();

const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
client.on("error", () => {});
client.on("advertise", (channels) => {
  const world = channels.find((c) => c.topic === "/world/scene");
  if (!world) {
    console.error(`world_client: no /world/scene among ${channels.map((c) => c.topic).join(", ")}`);
    process.exit(1);
  }
  if (world.schemaName !== "foxglove.SceneUpdate") {
    console.error(`world_client: /world/scene is a ${world.schemaName}`);
    process.exit(1);
  }
  client.subscribe(world.id);
});
let shown = false;
client.on("message", ({ data }) => {
  const update = JSON.parse(decoder.decode(data));
  const entity = update.entities.find((e) => e.id === id);
  if (entity) {
    last = `${entity.cubes.length} cubes, ${entity.spheres.length} spheres, ${entity.cylinders.length} cylinders`;
    if (entity.cubes.length >= Number(cubesText) && entity.spheres.length >= Number(spheresText) && !shown) {
      shown = true;
      console.log(`world_client: ${id} shown: ${last}`);
      if (gone !== "--gone") {
        client.close();
        process.exit(0);
      }
    }
  }
  if (shown && update.deletions.some((d) => d.id === id)) {
    console.log(`world_client: ${id} deleted once its engine ended`);
    client.close();
    process.exit(0);
  }
});
