#pragma once
// One scene for several devices, edited while they render it (docs/haptic-scene.md, "One scene, edited at run
// time"): the server's doors (and tests) add, remove, re-material and move objects from their own threads; each
// device's loop renders the newest scene without a lock or an allocation.
//
// How: every edit but a move makes a new Scene for every reader, built off the loop (a mesh's structure is built
// before it is added: an object carries its finished shape) and offered through one atomic pointer per reader;
// the reader's loop takes the newest offer at its next refresh and hands the scene it leaves back through a
// lock-free ring, and the editor frees the scenes handed back at its next edit (or collect()). A scene is never
// freed while a loop reads it, and a loop never frees one. A move goes to the object's pose track in every reader
// (scene/pose_track.hpp: played back at loop rate, one update interval behind, so an update is never a step);
// only objects made `moving` are played back.
//
// Objects keep a unique id (SceneObject::uid) across scenes, by which a device's proxy keeps what it knew about
// an object (GodObject::rebind) when the scene around it changes.
#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "hapticd/realtime/latest_value.hpp"
#include "hapticd/realtime/spsc_ring.hpp"
#include "hapticd/scene/pose_track.hpp"
#include "hapticd/scene/proxy.hpp"
#include "hapticd/scene/scene.hpp"

namespace hapticd::scene {

// What a device's hand does to the scene's objects: for each object it touches, the force on the object (the
// opposite of that object's share of the proxy's force on the hand; world frame, N) at the contact point.
struct ObjectContact {
  std::uint64_t object = 0;  // SceneObject::uid
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // the object's origin as the device rendered it (a moving
                                                     // object's played-back pose)
};
struct ContactReport {
  int count = 0;
  std::array<ObjectContact, kMaxContacts> contacts{};
  bool reported = false;                            // the device's proxy has been updated (its position is known)
  Eigen::Vector3d proxy = Eigen::Vector3d::Zero();  // the proxy's centre (the scene's frame)
  double radius = 0.0;                              // the proxy's
};
// A device's proxy as the editors (and the live view) see it.
struct DeviceProxy {
  std::string device;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double radius = 0.0;
  bool touching = false;
};
// ... as the editors see it: by device, with the object's name.
struct DeviceContact {
  std::string device;
  std::string object;
  std::uint64_t uid = 0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
};

class SharedScene {
 public:
  static constexpr std::size_t kMaxObjects = kMaxSceneObjects;

  // The objects' names must be unique (the scene file's are); at most kMaxObjects. Throws std::invalid_argument.
  explicit SharedScene(Scene initial = {});
  ~SharedScene();
  SharedScene(const SharedScene&) = delete;
  SharedScene& operator=(const SharedScene&) = delete;

  // One device's view, made off the loop; its refresh() and scene() belong to that device's loop thread.
  class Reader {
   public:
    // Real-time safe: takes the newest scene if one was offered (true then), and plays each moving object's pose
    // back at loop time now_ns.
    bool refresh(std::int64_t now_ns) noexcept;
    // The scene as of the last refresh(); valid until the next.
    [[nodiscard]] const Scene& scene() const noexcept { return *current_; }
    // Scenes taken since the reader was made (the first included); for tests and the live view.
    [[nodiscard]] std::uint64_t scenes_taken() const noexcept { return taken_; }
    // Real-time safe (the loop, after the proxy's update): what the proxy touches now, for the editors
    // (SharedScene::contacts; a triple buffer, no lock, no allocation).
    void report_contacts(const ProxyState& proxy, double radius = 0.0) noexcept;

   private:
    friend class SharedScene;
    Reader(std::unique_ptr<Scene> first, std::string device);
    std::atomic<Scene*> offered_{nullptr};
    Scene* current_ = nullptr;
    realtime::SpscRing<Scene*> returned_{64};
    Scene* stash_ = nullptr;              // a scene left while the ring was full: handed back at the next refresh
    std::vector<PoseTrack> tracks_;       // per object slot (SceneObject::slot), kMaxObjects
    std::vector<std::uint64_t> tracked_;  // the uid each slot's track follows (the loop's)
    std::uint64_t taken_ = 0;
    std::string device_;
    realtime::LatestValue<ContactReport> contacts_;
    ContactReport last_contacts_;  // the editors' (under the scene's mutex): the newest report taken
  };

  // Off the loop, before or while the loops run; the reader lives as long as this scene. device: whose it is.
  Reader& add_reader(std::string device = {});

  // Edits, from any thread but the loops' (serialised here). Each throws std::invalid_argument with the reason
  // (a name taken or unknown, too many objects) and changes nothing then.
  // Adds `object` (its name unique, its shape built); returns its uid.
  std::uint64_t add(SceneObject object);
  void remove(std::string_view name);
  void set_material(std::string_view name, const Material& material);
  // The object's new pose, played back by every reader (the object must be `moving`).
  void move(std::string_view name, const PoseUpdate& pose);

  // A copy of the newest scene (the objects' poses as added; moves are the readers').
  [[nodiscard]] Scene snapshot() const;
  // Any thread but the loops': what every device's hand does to the objects now (each reader's newest report; an
  // object removed since is left out).
  [[nodiscard]] std::vector<DeviceContact> contacts();
  // Any thread but the loops': each device's proxy as of its newest report (devices not yet reported left out).
  [[nodiscard]] std::vector<DeviceProxy> proxies();
  // A copy of the newest scene with each moving object at the pose it was last moved to (for drawing: the devices
  // render it one update interval behind, pose_track.hpp).
  [[nodiscard]] Scene drawn() const;
  // Frees the scenes the readers handed back (each edit does it too).
  void collect();

 private:
  [[nodiscard]] std::size_t index_of(std::string_view name) const;  // throws when unknown
  void publish();        // under mutex_: a copy of objects_ offered to every reader
  void free_returned();  // under mutex_: the scenes the readers handed back

  mutable std::mutex mutex_;
  std::vector<SceneObject> objects_;
  std::vector<Eigen::Isometry3d> moved_;  // per slot: a moving object's newest pose (drawn())
  std::vector<char> slot_used_;
  std::uint64_t next_uid_ = 1;
  std::deque<std::unique_ptr<Reader>> readers_;
};

}  // namespace hapticd::scene
