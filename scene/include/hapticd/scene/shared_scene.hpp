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

#include "hapticd/realtime/spsc_ring.hpp"
#include "hapticd/scene/pose_track.hpp"
#include "hapticd/scene/scene.hpp"

namespace hapticd::scene {

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

   private:
    friend class SharedScene;
    explicit Reader(std::unique_ptr<Scene> first);
    std::atomic<Scene*> offered_{nullptr};
    Scene* current_ = nullptr;
    realtime::SpscRing<Scene*> returned_{64};
    Scene* stash_ = nullptr;              // a scene left while the ring was full: handed back at the next refresh
    std::vector<PoseTrack> tracks_;       // per object slot (SceneObject::slot), kMaxObjects
    std::vector<std::uint64_t> tracked_;  // the uid each slot's track follows (the loop's)
    std::uint64_t taken_ = 0;
  };

  // Off the loop, before or while the loops run; the reader lives as long as this scene.
  Reader& add_reader();

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
  // Frees the scenes the readers handed back (each edit does it too).
  void collect();

 private:
  [[nodiscard]] std::size_t index_of(std::string_view name) const;  // throws when unknown
  void publish();        // under mutex_: a copy of objects_ offered to every reader
  void free_returned();  // under mutex_: the scenes the readers handed back

  mutable std::mutex mutex_;
  std::vector<SceneObject> objects_;
  std::vector<char> slot_used_;
  std::uint64_t next_uid_ = 1;
  std::deque<std::unique_ptr<Reader>> readers_;
};

}  // namespace hapticd::scene
