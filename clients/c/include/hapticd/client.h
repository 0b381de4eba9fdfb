/* hapticd's client API in C (docs/engines.md, "C"): every operation of the C++ client library
 * (hapticd/client/client.hpp) for programs and languages that cannot use C++ - a game engine's native plugin,
 * C# through P/Invoke, any FFI. Plain C structs of fixed size, errors as status codes with a message kept per
 * thread; no C++ exception or type crosses this interface.
 *
 * Versions: HAPTICD_C_API_VERSION is the version of this header; hapticd_api_version() the library's. The
 * library's symbols carry the version node HAPTICD_C_2 (a linker version script; the shared library is
 * libhapticd_c.so.2): a program built against this header runs against any library of the same major version. A
 * struct's layout never changes within a major version; new functions may be added, and an options struct may grow
 * at its end - its first field is its size (`.size = sizeof options`), so the library knows which fields a caller
 * has. Version 2 (from 1): option structs carry their size; one naming pattern; group requests through the device
 * calls; a device filter on the state callback; every function that can fail returns a status.
 *
 * Names: hapticd_<object>_<verb> - the object is the handle the call works on (hapticd_client_claim,
 * hapticd_engine_run); the library's own calls have none (hapticd_api_version, hapticd_last_error).
 *
 * Errors (libgit2's model): every call that can fail returns a hapticd_status; the message of the calling thread's
 * last failure is hapticd_last_error(), kept per thread as libgit2's git_error_last() is. Out-values are parameters.
 * MuJoCo's model - a caller's buffer per call (mj_loadXML's error, error_sz) and a process-wide handler
 * (mju_user_error, whose default exits) - was not taken: a buffer costs every signature two parameters, a
 * process-wide handler cannot tell threads apart, and this library never aborts or exits its host (a game engine).
 *
 * Threads and lifetimes, for every function unless it says otherwise:
 *  - A hapticd_client may be used from any thread, by several threads at once; hapticd_client_destroy must not
 *    run concurrently with any other call on the same client, nor from one of its callbacks.
 *  - Waiting calls (hapticd_wait_*, every request) block the calling thread up to their timeout; the others
 *    return at once.
 *  - Pointers passed in are only read during the call (nothing is kept); out-structs are written only on
 *    HAPTICD_OK (or, for a request, whenever a reply struct is given).
 *  - Callbacks run on the library's threads (said per callback); they may send commands and poll, but must not
 *    wait (no request, no hapticd_wait_*), set a callback, or destroy the client. The pointers they receive are
 *    valid only during the call.
 *  - hapticd_last_error() is the message of the last failing call of the calling thread; valid until that
 *    thread's next failing call.
 *
 * Real time: hapticd_client_latest_state and the hapticd_client_send* functions allocate no memory and do not wait
 * (tested), so an engine may call them every cycle.
 */
#ifndef HAPTICD_CLIENT_H
#define HAPTICD_CLIENT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The library defines HAPTICD_C_BUILDING when it builds itself (exporting); its users import. */
#if defined(_WIN32) && defined(HAPTICD_C_BUILDING)
#define HAPTICD_C_API __declspec(dllexport)
#elif defined(_WIN32)
#define HAPTICD_C_API __declspec(dllimport)
#else
#define HAPTICD_C_API __attribute__((visibility("default")))
#endif

#define HAPTICD_C_API_VERSION 2

/* The value types (states, descriptions, events, telemetry, fault reports, replies, commands), generated from the
 * data model's table (idl/hapticd_wire.toml; docs/wire-types.md). */
#include "hapticd/client_types.h"

/* ---- status ---- */
typedef enum hapticd_status {
  HAPTICD_OK = 0,
  HAPTICD_ERROR_INVALID_ARGUMENT = 1, /* a null pointer, an empty or too long name, a bad value */
  HAPTICD_ERROR_NOT_FOUND = 2,        /* no such device, group, state or report (yet) */
  HAPTICD_ERROR_TIMEOUT = 3,          /* nothing arrived within the timeout (a request: no reply) */
  HAPTICD_ERROR_REFUSED = 4,          /* the server answered and refused (the reply's message says why) */
  HAPTICD_ERROR_DDS = 5,              /* the DDS participant could not be made, or a write failed */
  HAPTICD_ERROR_INTERNAL = 6          /* anything else (the message says what) */
} hapticd_status;

/* The library's API version (HAPTICD_C_API_VERSION of the header it was built with). */
HAPTICD_C_API int hapticd_api_version(void);
/* The message of the calling thread's last failing call ("" when none). Never NULL. */
HAPTICD_C_API const char* hapticd_last_error(void);
/* A status's name ("HAPTICD_ERROR_TIMEOUT"). Never NULL. */
HAPTICD_C_API const char* hapticd_status_name(hapticd_status status);

/* hapticd_device_state.flags bits (hapticd/state_flags.hpp). */
enum {
  HAPTICD_FLAG_TORQUE_SATURATED = 1u << 0,
  HAPTICD_FLAG_ENGINE_ACTIVE = 1u << 1,
  HAPTICD_FLAG_ENGINE_STALE = 1u << 2,
  HAPTICD_FLAG_ESTOP = 1u << 3,
  HAPTICD_FLAG_FAULT = 1u << 4,
  HAPTICD_FLAG_SWITCHING = 1u << 5,
  HAPTICD_FLAG_SAFE_DAMPING = 1u << 6,
  HAPTICD_FLAG_LIMIT_ENGAGED = 1u << 7,
  HAPTICD_FLAG_RENDER_LIMITED = 1u << 8,
  HAPTICD_FLAG_THERMAL_DERATING = 1u << 9,
  HAPTICD_FLAG_PASSIVITY_CONTROL = 1u << 10
};

typedef enum hapticd_parameter_type {
  HAPTICD_PARAMETER_REAL = 0,
  HAPTICD_PARAMETER_INTEGER = 1,
  HAPTICD_PARAMETER_BOOLEAN = 2,
  HAPTICD_PARAMETER_TEXT = 3,
  HAPTICD_PARAMETER_REAL_VECTOR = 4
} hapticd_parameter_type;

/* ---- the client ---- */
typedef struct hapticd_client hapticd_client;

typedef struct hapticd_client_options {
  uint32_t size;         /* sizeof(hapticd_client_options): later versions may add fields after these */
  const char* client_id; /* 1..31 characters, unique per client: the owner name a claim records */
  int32_t domain_id;
  const char* cyclone_config; /* a Cyclone XML file, or NULL */
  /* Else the network, e.g. "interfaces=eth1;peers=192.0.2.2;multicast=false", or NULL: the environment's
   * HAPTICD_DDS_CONFIG or HAPTICD_DDS_NETWORK, else loopback only (docs/deployment.md). */
  const char* network;
  double command_deadline_s; /* 0: 0.05 s; must not exceed the server's deadline */
} hapticd_client_options;

/* Makes a client (one DDS participant). *out is NULL on failure. options->size must be at least the size of this
 * version's struct (HAPTICD_ERROR_INVALID_ARGUMENT otherwise, said so). */
HAPTICD_C_API hapticd_status hapticd_client_create(const hapticd_client_options* options, hapticd_client** out);
/* Ends it: its claims end with it (the server sees the participant go). NULL is ignored. Destroying a client twice,
 * or calling anything with a destroyed one, is undefined behaviour (as free() twice is): set your pointer to NULL. */
HAPTICD_C_API void hapticd_client_destroy(hapticd_client* client);

/* ---- devices ---- */
/* The descriptions received so far: up to capacity into out, the number there are into *count. */
HAPTICD_C_API hapticd_status hapticd_client_list_devices(hapticd_client* client, hapticd_device_info* out,
                                                         int32_t capacity, int32_t* count);
/* Waits for the device's description (started != 0: one that carries the start pose). */
HAPTICD_C_API hapticd_status hapticd_client_wait_for_device(hapticd_client* client, const char* device,
                                                            double timeout_s, int32_t started,
                                                            hapticd_device_info* out);
/* The newest state (HAPTICD_ERROR_NOT_FOUND before the first). Allocates nothing. */
HAPTICD_C_API hapticd_status hapticd_client_latest_state(hapticd_client* client, const char* device,
                                                         hapticd_device_state* out);
/* Waits for a state with serial > after. */
HAPTICD_C_API hapticd_status hapticd_client_wait_for_state(hapticd_client* client, const char* device, double timeout_s,
                                                           uint64_t after, hapticd_device_state* out);

/* ---- groups ---- */
HAPTICD_C_API hapticd_status hapticd_client_list_groups(hapticd_client* client, hapticd_group_info* out,
                                                        int32_t capacity, int32_t* count);
HAPTICD_C_API hapticd_status hapticd_client_wait_for_group(hapticd_client* client, const char* group, double timeout_s,
                                                           hapticd_group_info* out);
HAPTICD_C_API hapticd_status hapticd_client_latest_group_state(hapticd_client* client, const char* group,
                                                               hapticd_group_state* out);
HAPTICD_C_API hapticd_status hapticd_client_wait_for_group_state(hapticd_client* client, const char* group,
                                                                 double timeout_s, uint64_t after,
                                                                 hapticd_group_state* out);

/* ---- events, telemetry, fault reports ---- */
/* The events received since the last call, oldest first: up to capacity into out (the rest stay for the next
 * call), the number taken into *count. */
HAPTICD_C_API hapticd_status hapticd_client_take_events(hapticd_client* client, hapticd_event* out, int32_t capacity,
                                                        int32_t* count);
HAPTICD_C_API hapticd_status hapticd_client_latest_telemetry(hapticd_client* client, const char* device,
                                                             hapticd_telemetry* out);
HAPTICD_C_API hapticd_status hapticd_client_latest_fault_report(hapticd_client* client, const char* device,
                                                                hapticd_fault_report* out);

/* ---- callbacks (NULL removes; replacing is atomic: once the call returns the old one is not called again) ---- */
/* Every state of `device` (NULL or "": of every device), on the DDS receive thread, one at a time: answer it there.
 * One state callback per client: a second call replaces the first, filter and all. */
typedef void (*hapticd_state_callback)(const hapticd_device_state* state, void* user);
HAPTICD_C_API hapticd_status hapticd_client_on_state(hapticd_client* client, const char* device,
                                                     hapticd_state_callback callback, void* user);
/* Every event, on the client's thread (events are also kept for hapticd_client_take_events). */
typedef void (*hapticd_event_callback)(const hapticd_event* event, void* user);
HAPTICD_C_API hapticd_status hapticd_client_on_event(hapticd_client* client, hapticd_event_callback callback,
                                                     void* user);
/* A claim of this client ended without its release (the server handed the device on or freed it), once per claim,
 * on the DDS receive thread. Claim again or stop. */
typedef void (*hapticd_claim_lost_callback)(const char* device, const char* reason, void* user);
HAPTICD_C_API hapticd_status hapticd_client_on_claim_lost(hapticd_client* client, hapticd_claim_lost_callback callback,
                                                          void* user);
/* *lost: 1 when the newest claim of the device (or group) was lost so, else 0. */
HAPTICD_C_API hapticd_status hapticd_client_claim_lost(hapticd_client* client, const char* device, int32_t* lost);

/* ---- requests: HAPTICD_OK when accepted, HAPTICD_ERROR_REFUSED when refused, HAPTICD_ERROR_TIMEOUT without a
 * reply; reply (may be NULL) receives the reply whatever the status. A request without a reply is sent again
 * with the same id every 250 ms until the timeout; the server applies it once.
 * `target` names a device or a device group (session file `groups`): claim, release, emergency stop and recover
 * act on every device of a group at once (a group claim takes all or none); "*" stops or recovers every device of
 * the server. A name the client has not heard of yet is waited for (within the timeout) as either. ---- */
HAPTICD_C_API hapticd_status hapticd_client_claim(hapticd_client* client, const char* target, double timeout_s,
                                                  hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_client_release(hapticd_client* client, const char* target, double timeout_s,
                                                    hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_client_switch_scheme(hapticd_client* client, const char* device,
                                                          const char* scheme, double timeout_s, hapticd_reply* reply);
/* parameter: "<stage>.<name>", e.g. "virtual_model.coupling_stiffness_n_per_m". */
HAPTICD_C_API hapticd_status hapticd_client_set_parameter(hapticd_client* client, const char* device,
                                                          const char* parameter, const double* values,
                                                          int32_t value_count, double timeout_s, hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_client_get_parameter(hapticd_client* client, const char* device,
                                                          const char* parameter, double timeout_s,
                                                          hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_client_describe_parameter(hapticd_client* client, const char* device,
                                                               const char* parameter, double timeout_s,
                                                               hapticd_parameter_info* out, hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_client_emergency_stop(hapticd_client* client, const char* target, double timeout_s,
                                                           hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_client_recover(hapticd_client* client, const char* target, double timeout_s,
                                                    hapticd_reply* reply);
/* Simulated devices: "push" {fx, fy, fz[, ramp_s]}, "move" {dx, dy, dz[, duration_s]}, "grasp" {g}, "release". */
HAPTICD_C_API hapticd_status hapticd_client_operator_command(hapticd_client* client, const char* device,
                                                             const char* command, const double* values,
                                                             int32_t value_count, double timeout_s,
                                                             hapticd_reply* reply);

/* ---- engine commands (after a claim). Each is copied into its target's slot and written to DDS by the
 * library's sender thread (Cyclone allocates when it writes; the caller's thread does not): no allocation, no
 * wait. The newest command of a target is written; a write that failed (DDS Security refusing this identity) is
 * told by the next send to that target as HAPTICD_ERROR_DDS. Up to 16 devices and groups per client. ---- */
HAPTICD_C_API hapticd_status hapticd_client_send(hapticd_client* client, const char* device,
                                                 const hapticd_command* command);
HAPTICD_C_API hapticd_status hapticd_client_send_coupling(hapticd_client* client, const char* device,
                                                          const hapticd_pose* proxy, const hapticd_twist* proxy_twist,
                                                          uint64_t state_serial);
/* local_model may be NULL. */
HAPTICD_C_API hapticd_status hapticd_client_send_wrench(hapticd_client* client, const char* device,
                                                        const hapticd_wrench* wrench,
                                                        const hapticd_local_model* local_model, uint64_t state_serial);
HAPTICD_C_API hapticd_status hapticd_client_send_motion(hapticd_client* client, const char* device,
                                                        const hapticd_pose* pose, const hapticd_twist* twist,
                                                        uint64_t state_serial);
/* One command per device of the group (after hapticd_client_claim of the group), each naming its device, in the
 * group's order. */
HAPTICD_C_API hapticd_status hapticd_client_send_group(hapticd_client* client, const char* group,
                                                       const hapticd_command* commands, int32_t count);

/* ---- the session's haptic scene (docs/haptic-scene.md; a session with a `scene` section): the server renders its
 * objects at loop rate; an engine claims the scene and edits it at its own frame rate (the C++ library's
 * hapticd::client::SceneClient). Every call but hapticd_client_scene_move waits for the server's answer: HAPTICD_OK
 * accepted, HAPTICD_ERROR_REFUSED refused (the reason in reply->message and hapticd_last_error), HAPTICD_ERROR_TIMEOUT
 * none; reply may be NULL. Objects and materials are JSON as the scene file writes them (at most 4095 bytes). ---- */
HAPTICD_C_API hapticd_status hapticd_client_scene_claim(hapticd_client* client, double timeout_s, hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_client_scene_release(hapticd_client* client, double timeout_s,
                                                          hapticd_reply* reply);
/* object: {"name": "wall", "shape": "plane", "position": [...], "normal": [...], "material": {...}, "moving": 0/1} */
HAPTICD_C_API hapticd_status hapticd_client_scene_add(hapticd_client* client, const char* object, double timeout_s,
                                                      hapticd_reply* reply);
/* A mesh: object as for add (shape "mesh", no file); vertex_count vertices of three coordinates (m, the object's
 * frame), triangle_count triangles of three indices into them. Uploaded in parts, then checked and built by the
 * server (timeout_s for each part and for the add). */
HAPTICD_C_API hapticd_status hapticd_client_scene_add_mesh(hapticd_client* client, const char* object,
                                                           const double* vertices, int64_t vertex_count,
                                                           const uint32_t* triangles, int64_t triangle_count,
                                                           double timeout_s, hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_client_scene_remove(hapticd_client* client, const char* object, double timeout_s,
                                                         hapticd_reply* reply);
/* material: a name from the scene's materials, or a material in JSON. */
HAPTICD_C_API hapticd_status hapticd_client_scene_set_material(hapticd_client* client, const char* object,
                                                               const char* material, double timeout_s,
                                                               hapticd_reply* reply);
/* A moving object's new pose (world frame), played back by every device between updates. Not answered when it goes
 * through: HAPTICD_OK means written; a refusal is counted (hapticd_client_scene_refused_moves). */
HAPTICD_C_API hapticd_status hapticd_client_scene_move(hapticd_client* client, const char* object,
                                                       const hapticd_pose* pose);
/* *count: the refused moves so far; last (may be NULL, capacity bytes): the newest one's reason. */
HAPTICD_C_API hapticd_status hapticd_client_scene_refused_moves(hapticd_client* client, uint64_t* count, char* last,
                                                                int32_t capacity);
/* Every object: up to capacity into out, the number there are into *count. */
HAPTICD_C_API hapticd_status hapticd_client_scene_objects(hapticd_client* client, hapticd_scene_object* out,
                                                          int32_t capacity, int32_t* count, double timeout_s,
                                                          hapticd_reply* reply);
/* What every device's hand does to the objects now: up to capacity into out, the number there are into *count. */
HAPTICD_C_API hapticd_status hapticd_client_scene_contacts(hapticd_client* client, hapticd_scene_contact* out,
                                                           int32_t capacity, int32_t* count, double timeout_s,
                                                           hapticd_reply* reply);

/* ---- the engine helper (docs/engines.md, "The engine helper"; the C++ library's hapticd::client::Engine): finds
 * its device or group and waits until it started, claims it, answers each state through one callback, retakes a
 * claim the server ended, hands parameter events to a hook, ends on hapticd_engine_stop, a duration, the session's
 * end or a silent server (or waits for the server to come back and claims again), releases, says why. Commands go
 * out through the client's sender thread, as hapticd_client_send's. ---- */
typedef struct hapticd_engine hapticd_engine;

typedef struct hapticd_engine_options {
  uint32_t size;           /* sizeof(hapticd_engine_options): later versions may add fields after these */
  const char* name;        /* the prefix of its messages (standard output and error); NULL: "engine" */
  const char* device;      /* the device to claim; NULL or "" and no group: the only device on the domain */
  const char* group;       /* or the group to claim: one answer per group state, one group command */
  double wait_s;           /* for the device or group to appear and start, for a server to come back; 0: 10 s */
  double server_timeout_s; /* no state for this long: the session ended or the server is gone; 0: 3 s */
  double duration_s;       /* end after this long; 0: until hapticd_engine_stop or the server's end */
  int32_t wait_for_server; /* 1: after the session's end wait_s for the server to come back, claim again, go on */
} hapticd_engine_options;

typedef enum hapticd_engine_end_reason {
  HAPTICD_ENGINE_FINISHED = 0,      /* the duration passed */
  HAPTICD_ENGINE_STOPPED = 1,       /* hapticd_engine_stop */
  HAPTICD_ENGINE_SESSION_ENDED = 2, /* the session ended, or no state came (and no server came back) */
  HAPTICD_ENGINE_NO_DEVICE = 3,     /* the device or group did not appear or start */
  HAPTICD_ENGINE_CLAIM_REFUSED = 4, /* another engine holds it, or the claim hook refused */
  HAPTICD_ENGINE_CLAIM_LOST = 5,    /* the server ended the claim and another engine took the device */
  HAPTICD_ENGINE_FAILED = 6         /* the chores hook ended the run */
} hapticd_engine_end_reason;

typedef struct hapticd_engine_end {
  int32_t reason;    /* hapticd_engine_end_reason */
  int32_t exit_code; /* 0 finished, stopped or the session ended; 1 no device; 2 refused or failed; 3 claim lost */
  char message[HAPTICD_MESSAGE_SIZE];
} hapticd_engine_end;

/* One command per state, in the states' order (count: 1 for a device, the group's devices for a group); the
 * commands come zeroed and the helper sets their state serials and devices. Return 1 to send them, 0 to send
 * nothing for these states. On the DDS receive thread, one call at a time. */
typedef int32_t (*hapticd_engine_answer)(const hapticd_device_state* states, int32_t count, hapticd_command* commands,
                                         void* user);
/* After each accepted claim, before the first answer (again: 1 for a retaken claim or a server that came back).
 * Return 0 to end the run (it releases). On the thread of hapticd_engine_run. */
typedef int32_t (*hapticd_engine_claim_hook)(int32_t again, void* user);
/* Every 20 ms on the thread of hapticd_engine_run; return 0 to end the run. */
typedef int32_t (*hapticd_engine_chores_hook)(void* user);
/* A parameter of one of its devices was set (HAPTICD_EVENT_PARAMETER), on the thread of hapticd_engine_run as
 * soon as it came; answered_then: what hapticd_engine_answered said when it arrived. */
typedef void (*hapticd_engine_parameter_hook)(const hapticd_event* event, uint64_t answered_then, void* user);

/* The client must outlive the engine. options->size must be at least the size of this version's struct. */
HAPTICD_C_API hapticd_status hapticd_engine_create(hapticd_client* client, const hapticd_engine_options* options,
                                                   hapticd_engine** out);
HAPTICD_C_API void hapticd_engine_destroy(hapticd_engine* engine);
/* Finds the device or group and waits until it started; HAPTICD_ERROR_NOT_FOUND (said why) if it did not. */
HAPTICD_C_API hapticd_status hapticd_engine_connect(hapticd_engine* engine);
/* After hapticd_engine_connect: how many devices it answers for, and each one's description (with its start pose). */
HAPTICD_C_API hapticd_status hapticd_engine_device_count(hapticd_engine* engine, int32_t* count);
HAPTICD_C_API hapticd_status hapticd_engine_device(hapticd_engine* engine, int32_t index, hapticd_device_info* out);
/* Hooks, each optional; set them before hapticd_engine_run. */
HAPTICD_C_API hapticd_status hapticd_engine_on_claim(hapticd_engine* engine, hapticd_engine_claim_hook hook,
                                                     void* user);
HAPTICD_C_API hapticd_status hapticd_engine_on_chores(hapticd_engine* engine, hapticd_engine_chores_hook hook,
                                                      void* user);
HAPTICD_C_API hapticd_status hapticd_engine_on_parameter(hapticd_engine* engine, hapticd_engine_parameter_hook hook,
                                                         void* user);
/* Connects (unless done), claims, answers until it ends, releases; end (may be NULL) says why. For the run it takes
 * the client's state and event callbacks (hapticd_client_on_state, hapticd_client_on_event) and clears them when it
 * ends. HAPTICD_OK whatever the reason (end->exit_code tells success); an error status only for a bad argument or a
 * second run. */
HAPTICD_C_API hapticd_status hapticd_engine_run(hapticd_engine* engine, hapticd_engine_answer answer, void* user,
                                                hapticd_engine_end* end);
/* Ends the run at its next chore (any thread; not from a signal handler - set a flag and stop from the program). */
HAPTICD_C_API hapticd_status hapticd_engine_stop(hapticd_engine* engine);
/* *answered: the states answered so far (any thread). */
HAPTICD_C_API hapticd_status hapticd_engine_answered(hapticd_engine* engine, uint64_t* answered);

#ifdef __cplusplus
}
#endif

#endif /* HAPTICD_CLIENT_H */
