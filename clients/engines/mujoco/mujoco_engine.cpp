// hapticd-mujoco-engine: a physics engine renders the world (docs/engines.md, "Physics engines"). It loads an MJCF
// scene with a proxy body per device, claims a device or a group, and for every state steps MuJoCo with the
// proxies pulled towards the hands by the virtual coupling (the stiffness and damping the device's parameters
// give), then sends each proxy's pose and twist as a COUPLING command: the server renders the same spring-damper
// on the device. If the server goes away it waits for it, claims again and goes on with the same world.
#include <fmt/format.h>
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <mutex>

#include "../engine_main.hpp"
#include "hapticd/mujoco/coupled_world.hpp"

namespace {

// MuJoCo's fatal errors (out of memory in its arena) may not return into it: say so and end; the server fades
// the device's forces out when the commands stop.
void on_mujoco_error(const char* message) {
  const std::string line = fmt::format("hapticd-mujoco-engine: MuJoCo error: {}\n", message);
  (void)!write(STDERR_FILENO, line.data(), line.size());
  std::_Exit(2);
}

using hapticd::client::Client;
using hapticd::client::DeviceState;
using hapticd::client::EngineCommand;
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

bool same_gains(const CouplingGains& a, const CouplingGains& b) {
  return a.stiffness_n_per_m == b.stiffness_n_per_m && a.damping_n_s_per_m == b.damping_n_s_per_m &&
         a.rotational_stiffness_n_m_per_rad == b.rotational_stiffness_n_m_per_rad &&
         a.rotational_damping_n_m_s == b.rotational_damping_n_m_s;
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
  if (refusal.empty()) {
    if (!same_gains(now, running))
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

// What the command line gives beyond the helper's options.
struct Settings {
  std::string scene, arm_urdf, csv;
  std::vector<std::string> watch;
  double arm_radius = 0.02, world_rate = 30.0;
};

// The MuJoCo world coupled to the devices hapticd::client::Engine found: built at their start poses (so a restarted
// engine finds its objects where they were), stepped by each state on the receive thread (answer), set up again at
// each claim (the session's gains, the proxies at the hands), published and watched from the main thread (chores).
class MujocoEngine {
 public:
  MujocoEngine(Client& client, hapticd::client::Engine& engine, Settings settings)
      : client_(client), engine_(engine), settings_(std::move(settings)) {
    load_world();
    load_arms();
    open_csv();
  }

  bool claimed(bool again);
  bool answer(std::span<const DeviceState* const> states, std::span<EngineCommand> commands);
  bool chores();
  void follow(const hapticd::client::Event& event, std::uint64_t answered_then) {
    if (event.code != "virtual_model") return;
    for (std::size_t i = 0; i < devices().size(); ++i)
      follow_gains(client_, devices()[i], i, *world_, world_mutex_, [&] { return engine_.answered() - answered_then; });
  }
  void print_watched(const char* prefix);
  void summary() {
    std::lock_guard lock(world_mutex_);
    fmt::print("mujoco-engine: answered {} states; {:.1f} s of physics; time per state p50 {:.1f} us, p99 {:.1f} us\n",
               engine_.answered(), world_->time_s(), timing_.percentile(0.5), timing_.percentile(0.99));
  }

 private:
  [[nodiscard]] const std::vector<std::string>& devices() const { return engine_.devices(); }
  void load_world();
  void load_arms();
  void open_csv();
  void write_csv(std::span<const DeviceState* const> states, double time_s);

  Client& client_;
  hapticd::client::Engine& engine_;
  const Settings settings_;
  hapticd::mujoco::WorldOptions options_;
  std::unique_ptr<CoupledWorld> world_;
  std::vector<hapticd::mujoco::ArmModel> arms_;
  std::vector<bool> handle_device_;
  std::mutex world_mutex_;  // the receive thread steps the world; the main thread re-places proxies, publishes it
  std::vector<Hand> hands_;
  std::uint64_t last_cycle_ = 0;
  std::atomic<bool> unstable_{false};
  Timing timing_;
  std::ofstream out_;
  std::chrono::steady_clock::time_point last_world_, last_print_;
};

void MujocoEngine::load_world() {
  std::vector<Eigen::Vector3d> starts;
  for (std::size_t i = 0; i < devices().size(); ++i) {
    starts.push_back(engine_.description(i).start_pose->position);
    handle_device_.push_back(engine_.description(i).handle_device);
  }
  const double rate = engine_.description(0).rate_hz;
  options_.scene = settings_.scene;
  options_.devices = devices();
  options_.state_period_s = rate > 0.0 ? 1.0 / rate : 1e-3;
  options_.scene_to_world = hapticd::mujoco::scene_frame(starts);
  try {
    world_ = std::make_unique<CoupledWorld>(options_);
  } catch (const hapticd::mujoco::SceneError& e) {
    throw std::runtime_error(std::string("the scene does not load: ") + e.what());
  }
  hands_.resize(devices().size());
}

// The devices' arms, where the scene shows them.
void MujocoEngine::load_arms() {
  bool scene_shows_arm = false;
  for (std::size_t i = 0; i < devices().size(); ++i) scene_shows_arm = scene_shows_arm || world_->arm_bodies(i) > 0;
  if (settings_.arm_urdf.empty()) {
    if (!scene_shows_arm) return;
    fmt::print("mujoco-engine: the scene shows the arm; without --arm URDF its bodies are parked out of reach\n");
    for (std::size_t i = 0; i < devices().size(); ++i) world_->set_arm(i, {});
    return;
  }
  if (!scene_shows_arm) fmt::print("mujoco-engine: the scene has no arm bodies: --arm has nothing to move\n");
  for (std::size_t i = 0; i < devices().size(); ++i) {
    try {
      arms_.emplace_back(settings_.arm_urdf, settings_.arm_radius, engine_.description(i).base_pose);
    } catch (const std::exception& e) {
      throw std::runtime_error("--arm " + settings_.arm_urdf + ": " + e.what());
    }
  }
}

void MujocoEngine::open_csv() {
  if (settings_.csv.empty()) return;
  out_.open(settings_.csv);
  if (!out_) throw std::runtime_error("cannot write " + settings_.csv);
  out_ << "time_s";
  for (const std::string& d : devices())
    out_ << fmt::format(
        ",{0}_x,{0}_y,{0}_z,{0}_proxy_x,{0}_proxy_y,{0}_proxy_z,{0}_contact_fx,{0}_contact_fy,{0}_contact_fz", d);
  out_ << "\n";
}

// At each claim: the coupling's gains as the server's session has them now, the proxies at the newest states' hands.
bool MujocoEngine::claimed(bool again) {
  std::vector<CouplingGains> gains(devices().size());
  for (std::size_t i = 0; i < devices().size(); ++i) {
    if (const std::string e = read_gains(client_, devices()[i], gains[i]); !e.empty()) {
      fmt::print(stderr, "mujoco-engine: {}\n", e);
      return false;
    }
  }
  std::lock_guard lock(world_mutex_);
  for (std::size_t i = 0; i < devices().size(); ++i) {
    try {
      world_->set_gains(i, gains[i]);
    } catch (const hapticd::mujoco::SceneError& e) {
      fmt::print(stderr, "mujoco-engine: '{}': {}\n", devices()[i], e.what());
      return false;
    }
    const auto s = client_.wait_for_state(devices()[i], std::chrono::seconds(2));
    if (!s) return false;
    world_->place(i, hand_of(*s, handle_device_[i]));
    last_cycle_ = s->cycle;
  }
  if (!again)
    fmt::print("mujoco-engine: claimed '{}'; {} steps of {:.3f} ms per state, coupling {:.0f} N/m, {:.1f} N s/m\n",
               engine_.target(), world_->substeps(), 1e3 * world_->timestep_s(), world_->gains(0).stiffness_n_per_m,
               world_->gains(0).damping_n_s_per_m);
  return true;
}

// One state (or one group state): step the world by the cycles since the last one, answer with the proxies.
bool MujocoEngine::answer(std::span<const DeviceState* const> states, std::span<EngineCommand> commands) {
  const auto began = std::chrono::steady_clock::now();
  std::lock_guard lock(world_mutex_);
  if (unstable_.load()) return false;
  for (std::size_t i = 0; i < states.size(); ++i) hands_[i] = hand_of(*states[i], handle_device_[i]);
  for (std::size_t i = 0; i < arms_.size() && i < states.size(); ++i) {
    const DeviceState& st = *states[i];
    world_->set_arm(i, arms_[i].place(std::span<const double>(st.position.data(), static_cast<std::size_t>(st.dof))));
  }
  const std::uint64_t cycle = states.front()->cycle;
  const int periods = cycle > last_cycle_ ? static_cast<int>(std::min<std::uint64_t>(cycle - last_cycle_, 8)) : 1;
  last_cycle_ = cycle;
  // An unstable world put its proxies at the hands: this command pulls nowhere; it is the last one.
  if (!world_->step(hands_, periods).stable) unstable_.store(true);
  for (std::size_t i = 0; i < states.size(); ++i) {
    const hapticd::mujoco::Proxy p = world_->proxy(i);
    commands[i] = EngineCommand::coupling(p.pose, p.twist, states[i]->serial);
  }
  timing_.add(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - began).count());
  write_csv(states, states.front()->time_s());
  return true;
}

void MujocoEngine::write_csv(std::span<const DeviceState* const> states, double time_s) {
  if (!out_.is_open()) return;
  out_ << fmt::format("{:.4f}", time_s);
  for (std::size_t i = 0; i < states.size(); ++i) {
    const hapticd::mujoco::Proxy p = world_->proxy(i);
    const Eigen::Vector3d& h = hands_[i].pose.position;
    out_ << fmt::format(",{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.3f},{:.3f},{:.3f}", h.x(), h.y(), h.z(),
                        p.pose.position.x(), p.pose.position.y(), p.pose.position.z(), p.contact_force.x(),
                        p.contact_force.y(), p.contact_force.z());
  }
  out_ << "\n";
}

// The main thread's chores: the world's shapes for the live view, the watched bodies; an unstable world ends it.
bool MujocoEngine::chores() {
  const auto now = std::chrono::steady_clock::now();
  if (settings_.world_rate > 0.0 && now - last_world_ > std::chrono::duration<double>(1.0 / settings_.world_rate)) {
    last_world_ = now;
    std::vector<hapticd::mujoco::BodyShape> shapes;
    double physics_s = 0.0;
    {
      std::lock_guard lock(world_mutex_);
      shapes = world_->shapes();
      physics_s = world_->time_s();
    }
    (void)client_.publish_world(world_shapes(shapes), physics_s);
  }
  if (unstable_.load()) {
    fmt::print(stderr,
               "mujoco-engine: the world went unstable (MuJoCo reset it, or a proxy ran away): the proxies were put "
               "at the hands and the device is released; lower the coupling stiffness, give the proxy more mass or "
               "inertia, or make the scene's timestep smaller\n");
    return false;
  }
  if (!settings_.watch.empty() && now - last_print_ > std::chrono::seconds(1)) {
    last_print_ = now;
    print_watched("");
  }
  return true;
}

void MujocoEngine::print_watched(const char* prefix) {
  std::lock_guard lock(world_mutex_);
  for (const std::string& body : settings_.watch) {
    const auto pose = world_->body_pose(body);
    if (!pose) continue;
    const Eigen::Vector3d x = options_.scene_to_world.inverse() * pose->position;
    fmt::print("{}{} at ({:+.1f}, {:+.1f}, {:+.1f}) mm in the scene\n", prefix, body, 1e3 * x.x(), 1e3 * x.y(),
               1e3 * x.z());
  }
}

void add_options(CLI::App& app, Settings& s, double& server_timeout) {
  app.add_option("scene", s.scene, "the MJCF scene (a body 'proxy' or 'proxy_<device>' per device)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--server-timeout", server_timeout, "no state for this long: the server is gone, wait for it again")
      ->check(CLI::Range(0.1, 60.0));
  app.add_option("--arm", s.arm_urdf,
                 "the devices' robot model (URDF): their links move the scene's arm bodies (arm_<k>, arm_<device>_<k>)")
      ->check(CLI::ExistingFile);
  app.add_option("--arm-radius", s.arm_radius, "the links' radius where the model has no collision capsules [m]")
      ->check(CLI::Range(0.001, 0.2));
  app.add_option("--world-rate", s.world_rate, "publish the world's shapes for the live view this often (0: never)")
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--watch", s.watch, "print these bodies' positions now and then, and at the end");
  app.add_option("--csv", s.csv, "write time, each hand and proxy position and the proxies' contact forces here");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hapticd-mujoco-engine: a MuJoCo scene coupled to the devices through the virtual coupling"};
  hapticd::examples::EngineCommandLine command_line{.id = "mujoco-engine"};
  hapticd::examples::add_engine_options(app, command_line, hapticd::examples::Claims::device_or_group);
  Settings settings;
  double server_timeout = 1.0;
  add_options(app, settings, server_timeout);
  return hapticd::examples::engine_main("hapticd-mujoco-engine", app, argc, argv, [&] {
    mju_user_error = on_mujoco_error;
    Client client(command_line.client());
    hapticd::client::EngineOptions options = command_line.options("mujoco-engine");
    options.server_timeout = hapticd::client::Timeout(server_timeout);
    options.wait_for_server = true;  // a restarted server finds the world where it was
    options.chores_period = std::chrono::milliseconds(settings.world_rate > 50.0 ? 5 : 20);
    hapticd::client::Engine engine(client, options);
    if (!engine.connect()) return 1;
    MujocoEngine world(client, engine, settings);
    engine.on_claim([&](bool again) { return world.claimed(again); });
    engine.on_chores([&] { return world.chores(); });
    engine.on_parameter([&](const auto& event, std::uint64_t then) { world.follow(event, then); });
    world.print_watched("mujoco-engine: ");
    const auto end = engine.run([&](auto states, auto commands) { return world.answer(states, commands); });
    world.print_watched("mujoco-engine: at the end, ");
    world.summary();
    return end.exit_code();
  });
}
