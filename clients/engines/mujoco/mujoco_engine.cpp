// hapticd-mujoco-engine: a physics engine renders the world (docs/engines.md, "Physics engines"). It loads an MJCF
// scene with a proxy body per device, claims a device or a group, and for every state steps MuJoCo with the
// proxies pulled towards the hands by the virtual coupling (the stiffness and damping the device's parameters
// give), then sends each proxy's pose and twist as a COUPLING command: the server renders the same spring-damper
// on the device. If the server goes away it waits for it, claims again and goes on with the same world.
#include <fmt/format.h>
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <mutex>
#include <thread>

#include "../claim_keeper.hpp"
#include "../engine_main.hpp"
#include "hapticd/client/client.hpp"
#include "hapticd/mujoco/coupled_world.hpp"

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }

// MuJoCo's fatal errors (out of memory in its arena) may not return into it: say so and end; the server fades
// the device's forces out when the commands stop.
void on_mujoco_error(const char* message) {
  const std::string line = fmt::format("hapticd-mujoco-engine: MuJoCo error: {}\n", message);
  (void)!write(STDERR_FILENO, line.data(), line.size());
  std::_Exit(2);
}

using hapticd::client::Client;
using hapticd::client::DeviceState;
using hapticd::mujoco::CoupledWorld;
using hapticd::mujoco::CouplingGains;
using hapticd::mujoco::Hand;

// The coupling's gains as the device's virtual model renders them; an error when the model takes no coupling.
std::string read_gains(Client& client, const std::string& device, CouplingGains& gains) {
  const auto value = [&](const char* name, double& out) -> std::string {
    const auto r = client.get_parameter(device, fmt::format("virtual_model.{}", name));
    if (!r.answered) return fmt::format("'{}' did not answer a request for virtual_model.{}", device, name);
    if (!r.accepted || r.values.empty()) {
      return fmt::format("'{}' has no virtual_model.{} ({}): its session needs a virtual model with the coupling",
                         device, name, r.message);
    }
    out = r.values.front();
    return {};
  };
  double coupling = 0.0, rotation = 0.0;
  for (auto [name, out] : {std::pair{"coupling", &coupling},
                           {"coupling_stiffness_n_per_m", &gains.stiffness_n_per_m},
                           {"coupling_damping_n_s_per_m", &gains.damping_n_s_per_m}}) {
    if (std::string e = value(name, *out); !e.empty()) return e;
  }
  if (coupling == 0.0) return fmt::format("'{}' does not take the coupling (virtual_model.coupling is false)", device);
  if (value("rotation", rotation).empty() && rotation != 0.0) {
    (void)value("coupling_rotational_stiffness_n_m_per_rad", gains.rotational_stiffness_n_m_per_rad);
    (void)value("coupling_rotational_damping_n_m_s", gains.rotational_damping_n_m_s);
  }
  return {};
}

// The server's coupling gains changed (a parameter event of the device's virtual model): read them again and put
// them into the world if its step resolves them; if it does not, the engine refuses them - it says why and sets
// the server's gains back to the ones it runs, so the device's spring and the proxy's are the same one again.
// states: the states answered since the event came (printed: how long the old spring ran on).
void follow_gains(Client& client, const std::string& device, std::size_t index, CoupledWorld& world,
                  std::mutex& world_mutex, const std::function<std::uint64_t()>& states) {
  CouplingGains now;
  if (const std::string e = read_gains(client, device, now); !e.empty()) {
    fmt::print(stderr, "mujoco-engine: the coupling of '{}' changed, but: {}\n", device, e);
    return;
  }
  CouplingGains running;
  std::string refusal;
  {
    std::lock_guard lock(world_mutex);
    running = world.gains(index);
    try {
      world.set_gains(index, now);
    } catch (const hapticd::mujoco::SceneError& e) {
      refusal = e.what();
    }
  }
  const auto same = [](const CouplingGains& a, const CouplingGains& b) {
    return a.stiffness_n_per_m == b.stiffness_n_per_m && a.damping_n_s_per_m == b.damping_n_s_per_m &&
           a.rotational_stiffness_n_m_per_rad == b.rotational_stiffness_n_m_per_rad &&
           a.rotational_damping_n_m_s == b.rotational_damping_n_m_s;
  };
  if (refusal.empty()) {
    if (!same(now, running))
      fmt::print(
          "mujoco-engine: '{}' coupling now {:.0f} N/m, {:.1f} N s/m (the session's changed; in effect {} states "
          "after its event)\n",
          device, now.stiffness_n_per_m, now.damping_n_s_per_m, states());
    return;
  }
  fmt::print(stderr, "mujoco-engine: refused the coupling of '{}' ({:.0f} N/m, {:.1f} N s/m): {}; setting it back\n",
             device, now.stiffness_n_per_m, now.damping_n_s_per_m, refusal);
  bool restored = true;
  for (auto [name, value] : {std::pair{"coupling_stiffness_n_per_m", running.stiffness_n_per_m},
                             {"coupling_damping_n_s_per_m", running.damping_n_s_per_m}}) {
    const auto r = client.set_parameter(device, fmt::format("virtual_model.{}", name), {value});
    restored = restored && r.accepted;
    if (!r.accepted) fmt::print(stderr, "mujoco-engine: cannot set {} back: {}\n", name, r.message);
  }
  if (restored)
    fmt::print(stderr, "mujoco-engine: '{}' coupling back at {:.0f} N/m, {:.1f} N s/m\n", device,
               running.stiffness_n_per_m, running.damping_n_s_per_m);
}

// The hand a state gives: the virtual body the device follows (a joint device in admittance display) or the
// handle itself (a handle device); the handle's twist.
Hand hand_of(const DeviceState& s, bool handle_device) { return Hand{handle_device ? s.pose : s.target_pose, s.twist}; }

// The world's shapes as the live view takes them (hapticd_world): at most kMaxWorldShapes.
std::vector<hapticd::client::WorldShape> world_shapes(const std::vector<hapticd::mujoco::BodyShape>& shapes) {
  using hapticd::client::ShapeKind;
  std::vector<hapticd::client::WorldShape> out;
  for (const auto& s : shapes) {
    if (out.size() == static_cast<std::size_t>(hapticd::client::kMaxWorldShapes)) break;
    hapticd::client::WorldShape w;
    w.body.assign(s.body);
    w.kind = s.type == "sphere"      ? ShapeKind::sphere
             : s.type == "capsule"   ? ShapeKind::capsule
             : s.type == "cylinder"  ? ShapeKind::cylinder
             : s.type == "ellipsoid" ? ShapeKind::ellipsoid
             : s.type == "plane"     ? ShapeKind::plane
                                     : ShapeKind::box;
    w.size = s.size;
    w.color = s.rgba.cast<double>().cwiseMax(0.0).cwiseMin(1.0);
    w.pose = s.pose;
    out.push_back(w);
  }
  return out;
}

struct Timing {
  std::vector<double> per_state_us;
  void add(double us) {
    if (per_state_us.size() < 2'000'000) per_state_us.push_back(us);
  }
  [[nodiscard]] double percentile(double q) {
    if (per_state_us.empty()) return 0.0;
    auto at = per_state_us.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(per_state_us.size() - 1));
    std::nth_element(per_state_us.begin(), at, per_state_us.end());
    return *at;
  }
};

int run(int argc, char** argv) {
  CLI::App app{"hapticd-mujoco-engine: a MuJoCo scene coupled to the devices through the virtual coupling"};
  std::string scene, device, group, id = "mujoco-engine", csv, arm_urdf;
  std::vector<std::string> watch;
  int domain = 0;
  double duration = 0.0, wait = 10.0, server_timeout = 1.0, world_rate = 30.0, arm_radius = 0.02;
  app.add_option("scene", scene, "the MJCF scene (a body 'proxy' or 'proxy_<device>' per device)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--device", device, "the device to claim (default: the only one of the scene's session)");
  app.add_option("--group", group, "the group to claim instead (one proxy per device)")->excludes("--device");
  app.add_option("--id", id, "client id (the owner name)");
  app.add_option("--domain", domain, "DDS domain")->check(CLI::Range(0, 230));
  app.add_option("--duration", duration, "stop after this many seconds (0: until SIGINT/SIGTERM or the session ends)");
  app.add_option("--wait", wait,
                 "how long to wait for the device or group to appear, and for the server to come back after it ended");
  app.add_option("--server-timeout", server_timeout, "no state for this long: the server is gone, wait for it again")
      ->check(CLI::Range(0.1, 60.0));
  app.add_option("--arm", arm_urdf,
                 "the devices' robot model (URDF): their links move the scene's arm bodies (arm_<k>, arm_<device>_<k>)")
      ->check(CLI::ExistingFile);
  app.add_option("--arm-radius", arm_radius, "the links' radius where the model has no collision capsules [m]")
      ->check(CLI::Range(0.001, 0.2));
  app.add_option("--world-rate", world_rate, "publish the world's shapes for the live view this often (0: never)")
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--watch", watch, "print these bodies' positions now and then, and at the end");
  app.add_option("--csv", csv, "write time, each hand and proxy position and the proxies' contact forces here");
  CLI11_PARSE(app, argc, argv);
  if (std::getenv("HAPTICD_PARSE_ONLY") != nullptr) {  // the documentation's commands test (docs_commands)
    std::fputs("hapticd-mujoco-engine: the command line parsed (HAPTICD_PARSE_ONLY is set: nothing run)\n", stderr);
    return 0;
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  mju_user_error = on_mujoco_error;

  Client client({id, domain});
  const auto deadline = [&] { return std::chrono::duration<double>(wait); };
  // The devices: the group's, or the one named (or the only one on the domain).
  std::vector<std::string> devices;
  if (!group.empty()) {
    const auto g = client.wait_for_group(group, deadline());
    if (!g) {
      fmt::print(stderr, "mujoco-engine: no group '{}' on domain {} within {} s\n", group, domain, wait);
      return 1;
    }
    devices = g->devices;
  } else {
    if (device.empty()) {
      const auto until = std::chrono::steady_clock::now() + deadline();
      while (client.devices().empty() && std::chrono::steady_clock::now() < until && !g_stop.load()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      const auto found = client.devices();
      if (found.size() != 1) {
        fmt::print(stderr, "mujoco-engine: {} devices on domain {}: name one with --device\n", found.size(), domain);
        return 1;
      }
      device = found.front().device;
    }
    devices = {device};
  }
  // Their start poses place the scene (scene_frame), so a restarted engine finds its objects where they were.
  std::vector<Eigen::Vector3d> starts;
  std::vector<bool> handle_device;
  for (const std::string& d : devices) {
    const auto described = client.wait_for_device(d, deadline(), true);
    if (!described) {
      fmt::print(stderr, "mujoco-engine: device '{}' did not start within {} s\n", d, wait);
      return 1;
    }
    starts.push_back(described->start_pose->position);
    handle_device.push_back(described->handle_device);
  }
  const auto period_of = [&]() -> double {
    const auto d = client.wait_for_device(devices.front(), deadline());
    return d && d->rate_hz > 0.0 ? 1.0 / d->rate_hz : 1e-3;
  };
  hapticd::mujoco::WorldOptions options;
  options.scene = scene;
  options.devices = devices;
  options.state_period_s = period_of();
  options.scene_to_world = hapticd::mujoco::scene_frame(starts);
  std::unique_ptr<CoupledWorld> world;
  try {
    world = std::make_unique<CoupledWorld>(options);
  } catch (const hapticd::mujoco::SceneError& e) {
    fmt::print(stderr, "mujoco-engine: the scene does not load: {}\n", e.what());
    return 2;
  }
  // The devices' arms, where the scene shows them.
  std::vector<hapticd::mujoco::ArmModel> arms;
  bool scene_shows_arm = false;
  for (std::size_t i = 0; i < devices.size(); ++i) scene_shows_arm = scene_shows_arm || world->arm_bodies(i) > 0;
  if (!arm_urdf.empty()) {
    if (!scene_shows_arm) fmt::print("mujoco-engine: the scene has no arm bodies: --arm has nothing to move\n");
    for (const std::string& d : devices) {
      const auto described = client.wait_for_device(d, deadline());
      try {
        arms.emplace_back(arm_urdf, arm_radius, described ? described->base_pose : hapticd::Pose{});
      } catch (const std::exception& e) {
        fmt::print(stderr, "mujoco-engine: --arm {}: {}\n", arm_urdf, e.what());
        return 2;
      }
    }
  } else if (scene_shows_arm) {
    fmt::print("mujoco-engine: the scene shows the arm; without --arm URDF its bodies are parked out of reach\n");
    for (std::size_t i = 0; i < devices.size(); ++i) world->set_arm(i, {});
  }

  std::mutex world_mutex;  // the state callback steps the world; the main thread re-places proxies after a restart
  std::atomic<bool> running{false}, session_ending{false};
  std::atomic<std::uint64_t> answered{0}, unstable{0}, seen{0};
  std::uint64_t last_cycle = 0;
  std::vector<Hand> hands(devices.size());
  std::vector<hapticd::client::DeviceCommand> group_commands(devices.size());
  for (std::size_t i = 0; i < devices.size(); ++i) group_commands[i].device.assign(devices[i]);
  Timing timing;
  std::ofstream out;
  if (!csv.empty()) {
    out.open(csv);
    if (!out) {
      fmt::print(stderr, "mujoco-engine: cannot write {}\n", csv);
      return 2;
    }
    out << "time_s";
    for (const std::string& d : devices) {
      out << fmt::format(
          ",{0}_x,{0}_y,{0}_z,{0}_proxy_x,{0}_proxy_y,{0}_proxy_z,{0}_contact_fx,{0}_contact_fy,"
          "{0}_contact_fz",
          d);
    }
    out << "\n";
  }

  // One state (or one group state): step the world by the cycles since the last one, answer with the proxies.
  const auto answer = [&](std::span<const DeviceState* const> states, std::uint64_t cycle, double time_s) {
    const auto began = std::chrono::steady_clock::now();
    seen.fetch_add(1);
    std::lock_guard lock(world_mutex);
    if (!running.load()) return;
    for (std::size_t i = 0; i < states.size(); ++i) {
      hands[i] = hand_of(*states[i], handle_device[i]);
      const auto mode = states[i]->mode;
      if (mode == hapticd::client::Mode::stopping || mode == hapticd::client::Mode::off) session_ending.store(true);
    }
    for (std::size_t i = 0; i < arms.size() && i < states.size(); ++i) {
      const DeviceState& st = *states[i];
      world->set_arm(i, arms[i].place(std::span<const double>(st.position.data(), static_cast<std::size_t>(st.dof))));
    }
    const int periods = cycle > last_cycle ? static_cast<int>(std::min<std::uint64_t>(cycle - last_cycle, 8)) : 1;
    last_cycle = cycle;
    // An unstable world put its proxies at the hands: this command pulls nowhere; it is the last one.
    const bool stable = world->step(hands, periods).stable;
    for (std::size_t i = 0; i < states.size(); ++i) {
      const hapticd::mujoco::Proxy p = world->proxy(i);
      auto& c = group_commands[i].command;
      c.kind = hapticd::client::CommandKind::coupling;
      c.pose = p.pose;
      c.twist = p.twist;
      c.state_serial = states[i]->serial;
    }
    if (group.empty()) {
      client.send(devices.front(), group_commands.front().command);
    } else {
      client.send_group(group, group_commands);
    }
    answered.fetch_add(1);
    if (!stable) {
      unstable.fetch_add(1);
      running.store(false);
    }
    timing.add(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - began).count());
    if (out.is_open()) {
      out << fmt::format("{:.4f}", time_s);
      for (std::size_t i = 0; i < states.size(); ++i) {
        const hapticd::mujoco::Proxy p = world->proxy(i);
        out << fmt::format(",{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.3f},{:.3f},{:.3f}",
                           hands[i].pose.position.x(), hands[i].pose.position.y(), hands[i].pose.position.z(),
                           p.pose.position.x(), p.pose.position.y(), p.pose.position.z(), p.contact_force.x(),
                           p.contact_force.y(), p.contact_force.z());
      }
      out << "\n";
    }
  };
  if (group.empty()) {
    client.on_state([&](const DeviceState& s) {
      if (s.device != devices.front()) return;
      const DeviceState* one[] = {&s};
      answer(one, s.cycle, s.time_s());
    });
  } else {
    client.on_group_state([&](const hapticd::client::GroupState& g) {
      const auto n = static_cast<std::size_t>(g.device_count);
      if (g.group != group || n != devices.size() || n > g.states.size()) return;
      std::array<const DeviceState*, hapticd::client::kMaxGroupDevices> states{};
      for (std::size_t i = 0; i < n; ++i) states[i] = &g.states[i];
      answer(std::span(states.data(), n), g.cycle, g.states[0].time_s());
    });
  }

  // A parameter of a device's virtual model set at run time (hapticctl set): the main loop reads the gains again.
  std::atomic<bool> gains_changed{false};
  std::atomic<std::uint64_t> answered_at_event{0};
  std::mutex wake_mutex;  // the event wakes the main loop at once (it sleeps between its chores otherwise)
  std::condition_variable wake;
  client.on_event([&](const hapticd::client::Event& e) {
    if (e.kind != hapticd::client::EventKind::parameter || e.code != "virtual_model" ||
        std::find(devices.begin(), devices.end(), e.device) == devices.end())
      return;
    {
      std::lock_guard lock(wake_mutex);
      answered_at_event.store(answered.load());
      gains_changed.store(true);
    }
    wake.notify_one();
  });

  // Whatever way run() ends from here, the callbacks are gone before the locals they use (declared above) are.
  struct Unhook {
    Client& c;
    ~Unhook() {
      c.on_state({});
      c.on_group_state({});
      c.on_event({});
    }
  } unhook{client};

  // Claims (again): the coupling's gains as the server's session has them now, the proxies placed at the hands of
  // the newest states.
  const auto claim = [&]() -> bool {
    std::vector<CouplingGains> gains(devices.size());
    for (std::size_t i = 0; i < devices.size(); ++i) {
      if (const std::string e = read_gains(client, devices[i], gains[i]); !e.empty()) {
        fmt::print(stderr, "mujoco-engine: {}\n", e);
        return false;
      }
    }
    const auto reply = group.empty() ? client.claim(devices.front()) : client.claim_group(group);
    if (!reply.accepted) {
      fmt::print(stderr, "mujoco-engine: cannot claim '{}': {}\n", group.empty() ? devices.front() : group,
                 reply.message);
      return false;
    }
    std::lock_guard lock(world_mutex);
    for (std::size_t i = 0; i < devices.size(); ++i) {
      try {
        world->set_gains(i, gains[i]);
      } catch (const hapticd::mujoco::SceneError& e) {
        fmt::print(stderr, "mujoco-engine: '{}': {}\n", devices[i], e.what());
        return false;
      }
      const auto s = client.wait_for_state(devices[i], deadline());
      if (!s) return false;
      world->place(i, hand_of(*s, handle_device[i]));
      last_cycle = s->cycle;
    }
    running.store(true);
    return true;
  };
  if (!claim()) return 2;
  const std::string claimed = group.empty() ? devices.front() : group;
  fmt::print("mujoco-engine: claimed '{}'; {} steps of {:.3f} ms per state, coupling {:.0f} N/m, {:.1f} N s/m\n",
             claimed, world->substeps(), 1e3 * world->timestep_s(), world->gains(0).stiffness_n_per_m,
             world->gains(0).damping_n_s_per_m);
  const auto print_watched = [&](const char* prefix) {
    std::lock_guard lock(world_mutex);
    for (const std::string& body : watch) {
      const auto pose = world->body_pose(body);
      if (!pose) continue;
      const Eigen::Vector3d x = options.scene_to_world.inverse() * pose->position;
      fmt::print("{}{} at ({:+.1f}, {:+.1f}, {:+.1f}) mm in the scene\n", prefix, body, 1e3 * x.x(), 1e3 * x.y(),
                 1e3 * x.z());
    }
  };
  print_watched("mujoco-engine: ");

  const auto start = std::chrono::steady_clock::now();
  auto last_progress = start, last_print = start;
  std::uint64_t last_answered = 0;
  int code = 0;
  auto last_world = start;
  while (!g_stop.load()) {
    {
      std::unique_lock lock(wake_mutex);
      wake.wait_for(lock, std::chrono::milliseconds(world_rate > 50.0 ? 5 : 20), [&] { return gains_changed.load(); });
    }
    const auto now = std::chrono::steady_clock::now();
    if (world_rate > 0.0 && now - last_world > std::chrono::duration<double>(1.0 / world_rate)) {
      last_world = now;
      std::vector<hapticd::mujoco::BodyShape> shapes;
      double physics_s = 0.0;
      {
        std::lock_guard lock(world_mutex);
        shapes = world->shapes();
        physics_s = world->time_s();
      }
      (void)client.publish_world(world_shapes(shapes), physics_s);
    }
    if (gains_changed.exchange(false) && running.load())
      for (std::size_t i = 0; i < devices.size(); ++i)
        follow_gains(client, devices[i], i, *world, world_mutex, [&] { return answered.load() - answered_at_event; });
    if (duration > 0.0 && now - start > std::chrono::duration<double>(duration)) break;
    if (unstable.load() > 0) {
      fmt::print(stderr,
                 "mujoco-engine: the world went unstable (MuJoCo reset it, or a proxy ran away): the proxies were put "
                 "at the hands and the device is released; lower the coupling stiffness, give the proxy more mass or "
                 "inertia, or make the scene's timestep smaller\n");
      code = 2;
      break;
    }
    if (answered.load() != last_answered) {
      last_answered = answered.load();
      last_progress = now;
      if (!group.empty() || devices.size() == 1) {
        if (!hapticd::examples::keep_claim(client, claimed, "mujoco-engine", !group.empty(), devices.front())) {
          code = hapticd::examples::kExitClaimLost;
          break;
        }
      }
      if (!watch.empty() && now - last_print > std::chrono::seconds(1)) {
        last_print = now;
        print_watched("");
      }
      continue;
    }
    if (now - last_progress < std::chrono::duration<double>(server_timeout)) continue;
    // No state for a while: the session ended (its last states were answered) or the server is gone. Wait for
    // states to come again (the server restarted), then claim again; the world goes on where it was.
    running.store(false);
    if (session_ending.exchange(false)) {
      fmt::print("mujoco-engine: the session ended; waiting up to {} s for the server to come back\n", wait);
    } else {
      fmt::print("mujoco-engine: no state for {:.1f} s; waiting up to {} s for the server to come back\n",
                 server_timeout, wait);
    }
    const std::uint64_t before = seen.load();
    const auto until = std::chrono::steady_clock::now() + deadline();
    while (!g_stop.load() && seen.load() == before && std::chrono::steady_clock::now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (seen.load() == before) {
      if (!g_stop.load()) fmt::print("mujoco-engine: no server came back within {} s\n", wait);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // its loop runs: the start pose is published
    if (!claim()) {
      code = 2;
      break;
    }
    fmt::print("mujoco-engine: the server is back; claimed '{}' again\n", claimed);
    last_progress = std::chrono::steady_clock::now();
  }
  running.store(false);
  client.on_state({});
  client.on_group_state({});
  client.on_event({});
  if (group.empty()) {
    (void)client.release(devices.front(), std::chrono::milliseconds(500));
  } else {
    (void)client.release_group(group, std::chrono::milliseconds(500));
  }
  print_watched("mujoco-engine: at the end, ");
  std::lock_guard lock(world_mutex);
  fmt::print("mujoco-engine: answered {} states; {:.1f} s of physics; time per state p50 {:.1f} us, p99 {:.1f} us\n",
             answered.load(), world->time_s(), timing.percentile(0.5), timing.percentile(0.99));
  return code;
}

}  // namespace

int main(int argc, char** argv) { return hapticd::examples::guarded_main("hapticd-mujoco-engine", run, argc, argv); }
