#pragma once
// The session's haptic scene at the gate (docs/haptic-scene.md, "Engines edit the scene"): who owns it and what the
// owner's edits do, whichever door they came through. Owned like a device: one owner at a time (claim, release;
// the claim ends when the channel that made it is gone - a connection closed, checked on the gate's service
// thread); only the owner edits; anyone may list the objects, draw them and ask what the hands do to them (contacts:
// each device's force and torque on each object it touches, as of the devices' latest cycles - an engine asks at its
// frame rate and applies them to its copies of the objects). An edit is made on the door's thread, off the loop
// (an object is parsed and built there; the devices take the new scene whole at their next cycle). Edits that
// remake the scene (add, remove, material) are held to kRemakesPerSecond per owner (a burst of as many); moves to
// the door's own message rate. Every refusal is counted and says why; a refused edit changes nothing.
//
// Meshes come in parts (upload): each part's vertices and triangles (their indices count from the upload's first
// vertex) are appended in order, the parts bounded by the door's message size and all the uploads held together by
// kMaxUploadTriangles and kMaxUploadVertices (72 MB at most); an add that names the finished upload (`shape: mesh,
// upload: NAME`) checks and builds it. At most kMaxUploads uploads at once, the owner's only: they end with the claim.
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gate/peer.hpp"
#include "hapticd/scene_service.hpp"

namespace hapticd::server {

class SceneGate {
 public:
  static constexpr double kRemakesPerSecond = 50.0;
  static constexpr std::size_t kMaxUploads = 4;
  static constexpr std::size_t kMaxUploadTriangles = 2'000'000;
  static constexpr std::size_t kMaxUploadVertices = 2'000'000;
  static constexpr int kMaxUploadParts = 100'000;

  explicit SceneGate(SceneService& scene) : scene_(scene) {}

  // A drawing's mesh corners come in pages of kDrawPage triangles (a page of 400 is about 25 kB of JSON).
  static constexpr std::size_t kDrawPage = 400;
  static constexpr std::size_t kMaxDrawTriangles = 20'000;

  enum class Op : std::uint8_t { claim, release, add, remove, material, move, list, contacts, upload, draw };
  struct Edit {
    Op op = Op::list;
    std::string_view name;    // the object (remove, material, move)
    std::string_view text;    // the object (add) or the material (material): as the scene file writes it, YAML or JSON
    Pose pose;                // move
    std::string_view upload;  // upload: the upload's name; add: the finished upload the object is made of ("": none)
    int part = 0, parts = 0;  // upload: this part's number (from 0) of how many
    std::span<const double> vertices;          // upload: this part's, three coordinates each
    std::span<const std::uint32_t> triangles;  // upload: this part's, three indices each
    // draw: with no name, every object without its triangles and every proxy; with a mesh's name, that mesh
    // drawn with at most max_triangles of its triangles (every k-th), those from `first` on (kDrawPage of them).
    std::size_t max_triangles = 0, first = 0;
  };
  struct Reply {
    Reply() = default;
    Reply(bool accepted_, std::string message_) : accepted(accepted_), message(std::move(message_)) {}
    bool accepted = false;
    std::string message;
    std::optional<std::vector<SceneObjectSummary>> objects;  // the answer to list (none for any other op)
    std::optional<std::vector<SceneContact>> contacts;       // the answer to contacts
    std::optional<SceneDrawing> drawing;                     // the answer to draw
    std::size_t drawn = 0;                                   // draw of a mesh: how many triangles it is drawn with
  };

  // A door's thread: `sender`'s edit (its client id `client`, for messages and the owner's name); now_ns: the
  // door's monotonic clock, for the rate limit.
  Reply apply(const Edit& edit, const Sender& sender, std::string_view client, std::int64_t now_ns);
  // The gate's service thread: the claim ends when its channel is gone (as the door says). True when it ended.
  bool check_claim(const std::function<bool(const Sender&)>& gone);

  [[nodiscard]] std::string owner() const;
  [[nodiscard]] std::uint64_t edits() const noexcept { return edits_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t refused() const noexcept { return refused_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t rate_limited() const noexcept { return rate_limited_.load(std::memory_order_relaxed); }

 private:
  Reply edit(const Edit& e);  // under mutex_, from the owner
  Reply draw(const Edit& e);
  Reply take_part(const Edit& e);
  Reply add_upload(const Edit& e);

  struct Upload {
    std::string name;
    int parts = 0, next = 0;  // how many, the one expected next (parts: finished)
    std::vector<double> vertices;
    std::vector<std::uint32_t> triangles;
  };

  SceneService& scene_;
  mutable std::mutex mutex_;
  std::string owner_;  // the owner's client id ("": free)
  Sender owner_channel_;
  std::vector<Upload> uploads_;  // the owner's
  double allowance_ = kRemakesPerSecond;
  std::int64_t refilled_ns_ = 0;
  std::atomic<std::uint64_t> edits_{0}, refused_{0}, rate_limited_{0};
};

}  // namespace hapticd::server
