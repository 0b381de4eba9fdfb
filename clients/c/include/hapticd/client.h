/* hapticd's client API in C (docs/engines.md, "C"): every operation of the C++ client library
 * (hapticd/client/client.hpp) for programs and languages that cannot use C++ - a game engine's native plugin,
 * C# through P/Invoke, any FFI. Plain C structs of fixed size, errors as status codes with a message kept per
 * thread; no C++ exception or type crosses this interface.
 *
 * Versions: HAPTICD_C_API_VERSION is the version of this header; hapticd_api_version() the library's. The
 * library's symbols carry the version node HAPTICD_C_1 (a linker version script): a program built against this
 * header runs against any library of the same major version. A struct's layout never changes within a major
 * version; new functions may be added.
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
 * Real time: hapticd_latest_state and the hapticd_send* functions allocate no memory and do not wait (tested),
 * so an engine may call them every cycle.
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

#define HAPTICD_C_API_VERSION 1

#define HAPTICD_NAME_SIZE 32     /* names: up to 31 characters and a terminating zero */
#define HAPTICD_MESSAGE_SIZE 256 /* messages: longer ones are cut */
#define HAPTICD_MAX_JOINTS 10
#define HAPTICD_MAX_VALUES 16        /* values of a request or reply */
#define HAPTICD_MAX_GROUP_DEVICES 8  /* devices of a group */
#define HAPTICD_MAX_SCHEMES 16       /* schemes listed in a device's description */
#define HAPTICD_MAX_FAULT_RECORDS 64 /* cycles kept of a fault report (its newest) */
#define HAPTICD_REJECT_REASONS 8

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

/* ---- values (world frame; twists and wrenches at the handle point; quaternions w, x, y, z) ---- */
typedef struct hapticd_vec3 {
  double x, y, z;
} hapticd_vec3;
typedef struct hapticd_quat {
  double w, x, y, z;
} hapticd_quat;
typedef struct hapticd_pose {
  hapticd_vec3 position; /* m */
  hapticd_quat orientation;
} hapticd_pose;
typedef struct hapticd_twist {
  hapticd_vec3 linear;  /* m/s */
  hapticd_vec3 angular; /* rad/s */
} hapticd_twist;
typedef struct hapticd_wrench {
  hapticd_vec3 force;  /* N */
  hapticd_vec3 torque; /* N m */
} hapticd_wrench;

typedef enum hapticd_mode {
  HAPTICD_MODE_STARTING = 0,
  HAPTICD_MODE_RUNNING = 1,
  HAPTICD_MODE_STOPPING = 2,
  HAPTICD_MODE_SAFE = 3,
  HAPTICD_MODE_OFF = 4
} hapticd_mode;

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

typedef struct hapticd_loop_summary {
  double rate_hz;
  uint64_t cycles;
  uint64_t overruns;
  double latency_max_us;
  double compute_max_us;
} hapticd_loop_summary;

/* One published state of a device. */
typedef struct hapticd_device_state {
  char device[HAPTICD_NAME_SIZE];
  uint64_t serial; /* one per published state, increasing: answer it in the command */
  uint64_t cycle;
  int64_t loop_time_ns;
  hapticd_pose pose; /* the measured handle */
  hapticd_twist twist;
  hapticd_wrench operator_wrench;    /* the operator's wrench on the handle */
  hapticd_wrench environment_wrench; /* what the rendered environment applies to the handle */
  hapticd_pose target_pose;          /* the chain's desired pose (the virtual body; a handle device's handle) */
  int32_t dof;
  double position[HAPTICD_MAX_JOINTS]; /* the first dof: rad or m (a handle device's axes) */
  double velocity[HAPTICD_MAX_JOINTS];
  double torque[HAPTICD_MAX_JOINTS]; /* commanded */
  uint32_t buttons;                  /* bit i: button i pressed */
  double gripper;                    /* the gripper's opening (rad), 0 without one */
  int32_t mode;                      /* hapticd_mode */
  uint32_t flags;                    /* HAPTICD_FLAG_* */
  char fault[HAPTICD_NAME_SIZE];     /* "" when none */
  char scheme[HAPTICD_NAME_SIZE];
  char owner[HAPTICD_NAME_SIZE]; /* "" when free */
  uint64_t engine_serial;        /* the newest engine command the loop has applied */
  hapticd_loop_summary loop;
} hapticd_device_state;

typedef struct hapticd_scheme_info {
  char name[HAPTICD_NAME_SIZE];
  char virtual_model[HAPTICD_NAME_SIZE]; /* the plugin engine commands reach ("" none) */
} hapticd_scheme_info;

/* A device's description. */
typedef struct hapticd_device_info {
  char device[HAPTICD_NAME_SIZE];
  int32_t version; /* the server's data model version */
  char device_plugin[HAPTICD_NAME_SIZE];
  int32_t simulated; /* 1: accepts operator commands */
  double rate_hz;
  int32_t dof;
  char joint_names[HAPTICD_MAX_JOINTS][HAPTICD_NAME_SIZE];
  double position_min[HAPTICD_MAX_JOINTS], position_max[HAPTICD_MAX_JOINTS], velocity_max[HAPTICD_MAX_JOINTS];
  double torque_peak[HAPTICD_MAX_JOINTS], torque_continuous[HAPTICD_MAX_JOINTS];
  char base_frame[HAPTICD_NAME_SIZE];
  hapticd_pose base_pose;
  char handle_frame[HAPTICD_NAME_SIZE];
  int32_t has_start_pose; /* 1: start_pose is the handle at the first cycle */
  hapticd_pose start_pose;
  double workspace_radius; /* m around the start pose (0: not given) */
  hapticd_vec3 workspace_min, workspace_max;
  int32_t scheme_count;
  hapticd_scheme_info schemes[HAPTICD_MAX_SCHEMES];
  double command_deadline_s; /* engine commands must arrive at least this often */
  double command_fade_s;     /* after a missed deadline the forces fade to zero over this time */
  int32_t handle_device;     /* 1: a handle device (its joints are the handle's axes) */
  int32_t handle_dof;        /* 3 or 6; 0 for a joint device */
  int32_t has_gripper;
  int32_t button_count;
} hapticd_device_info;

typedef struct hapticd_group_info {
  char group[HAPTICD_NAME_SIZE];
  int32_t version;
  int32_t device_count;
  char devices[HAPTICD_MAX_GROUP_DEVICES][HAPTICD_NAME_SIZE]; /* in the group's order */
  double min_distance_m;
  double repulsion_distance_m;
  int32_t own_loop;
} hapticd_group_info;

/* Every device of a group from one cycle. */
typedef struct hapticd_group_state {
  char group[HAPTICD_NAME_SIZE];
  uint64_t serial;
  uint64_t cycle;
  int64_t loop_time_ns;
  double clearance_m; /* -1: not measured */
  int32_t device_count;
  hapticd_device_state states[HAPTICD_MAX_GROUP_DEVICES]; /* the first device_count */
} hapticd_group_state;

typedef enum hapticd_event_kind {
  HAPTICD_EVENT_FAULT = 0,
  HAPTICD_EVENT_ESTOP = 1,
  HAPTICD_EVENT_MODE = 2,
  HAPTICD_EVENT_SCHEME = 3,
  HAPTICD_EVENT_OWNER = 4,
  HAPTICD_EVENT_ENGINE_STALE = 5,
  HAPTICD_EVENT_ENGINE_REJECTED = 6,
  HAPTICD_EVENT_RECOVERED = 7,
  HAPTICD_EVENT_RECORDING = 8,
  HAPTICD_EVENT_PARAMETER = 9 /* a parameter was set at run time: code its plugin slot, message "name = values" */
} hapticd_event_kind;

typedef struct hapticd_event {
  char device[HAPTICD_NAME_SIZE];
  uint64_t serial;
  int64_t loop_time_ns;
  int32_t kind; /* hapticd_event_kind */
  char code[HAPTICD_NAME_SIZE];
  char message[HAPTICD_MESSAGE_SIZE];
} hapticd_event;

typedef struct hapticd_telemetry {
  char device[HAPTICD_NAME_SIZE];
  int64_t wall_time_ns;
  hapticd_loop_summary loop;
  uint64_t states_published, commands_received, commands_accepted;
  /* rejected commands: malformed, non-finite, out of bounds, out of order, stale, not the owner, wrong kind, other */
  uint64_t rejected[HAPTICD_REJECT_REASONS];
  uint64_t requests, deadline_misses, scheme_switches;
  uint64_t saturated_cycles, limited_cycles, render_limited_cycles;
  uint64_t faults, recoveries;
  double thermal_load;
  double dissipated_j;
} hapticd_telemetry;

typedef struct hapticd_fault_cycle {
  uint64_t cycle;
  int64_t loop_time_ns;
  double position[HAPTICD_MAX_JOINTS], velocity[HAPTICD_MAX_JOINTS], torque[HAPTICD_MAX_JOINTS];
  hapticd_vec3 handle_position, handle_velocity, operator_force, environment_force;
  uint32_t flags;
} hapticd_fault_cycle;

/* A fault and the cycles before it (oldest first; the newest HAPTICD_MAX_FAULT_RECORDS). */
typedef struct hapticd_fault_report {
  char device[HAPTICD_NAME_SIZE];
  uint64_t serial;
  char fault[HAPTICD_NAME_SIZE];
  char message[HAPTICD_MESSAGE_SIZE];
  uint64_t cycle;
  int64_t loop_time_ns;
  int32_t dof;
  int32_t record_count;
  hapticd_fault_cycle records[HAPTICD_MAX_FAULT_RECORDS];
} hapticd_fault_report;

/* A request's reply. */
typedef struct hapticd_reply {
  int32_t answered; /* 0: no reply within the timeout */
  int32_t accepted;
  char message[HAPTICD_MESSAGE_SIZE];
  int32_t value_count;
  double values[HAPTICD_MAX_VALUES]; /* get_parameter: the value in effect (a boolean as 0 or 1) */
} hapticd_reply;

typedef enum hapticd_parameter_type {
  HAPTICD_PARAMETER_REAL = 0,
  HAPTICD_PARAMETER_INTEGER = 1,
  HAPTICD_PARAMETER_BOOLEAN = 2,
  HAPTICD_PARAMETER_TEXT = 3,
  HAPTICD_PARAMETER_REAL_VECTOR = 4
} hapticd_parameter_type;

/* A parameter's declaration and value in effect. */
typedef struct hapticd_parameter_info {
  char name[64]; /* "<stage>.<parameter>" */
  int32_t type;  /* hapticd_parameter_type */
  char unit[HAPTICD_NAME_SIZE];
  char description[HAPTICD_MESSAGE_SIZE];
  int32_t tunable;
  int32_t has_minimum, has_maximum, minimum_exclusive;
  double minimum, maximum;
  char value_text[HAPTICD_MESSAGE_SIZE];
  int32_t value_count;
  double values[HAPTICD_MAX_VALUES];
} hapticd_parameter_info;

/* ---- what an engine sends ---- */
/* A wrench's local model: every cycle until the next command the server applies
 * wrench + stiffness .* (anchor - x) - damping .* xd. */
typedef struct hapticd_local_model {
  hapticd_pose anchor;
  double stiffness[6]; /* N/m (3), N m/rad (3) */
  double damping[6];   /* N s/m (3), N m s/rad (3) */
} hapticd_local_model;

typedef enum hapticd_command_kind {
  HAPTICD_COMMAND_WRENCH = 0,   /* impedance type: a wrench (with an optional local model) */
  HAPTICD_COMMAND_COUPLING = 1, /* impedance type: the proxy pose and twist of the virtual coupling */
  HAPTICD_COMMAND_MOTION = 2    /* admittance type: the desired motion of the handle */
} hapticd_command_kind;

typedef struct hapticd_command {
  char device[HAPTICD_NAME_SIZE]; /* a group command: the device it is for */
  int32_t kind;                   /* hapticd_command_kind */
  uint64_t state_serial;          /* the state it answers (0: none) */
  hapticd_wrench wrench;          /* WRENCH */
  int32_t has_local_model;
  hapticd_local_model local_model;
  hapticd_pose pose;   /* COUPLING: the proxy; MOTION: the desired pose */
  hapticd_twist twist; /* COUPLING: the proxy's twist; MOTION: the desired twist */
} hapticd_command;

/* ---- the client ---- */
typedef struct hapticd_client hapticd_client;

typedef struct hapticd_client_options {
  const char* client_id; /* 1..31 characters, unique per client: the owner name a claim records */
  int32_t domain_id;
  const char* cyclone_config; /* a Cyclone XML file, or NULL */
  /* Else the network, e.g. "interfaces=eth1;peers=192.0.2.2;multicast=false", or NULL: the environment's
   * HAPTICD_DDS_CONFIG or HAPTICD_DDS_NETWORK, else loopback only (docs/deployment.md). */
  const char* network;
  double command_deadline_s; /* 0: 0.05 s; must not exceed the server's deadline */
} hapticd_client_options;

/* Makes a client (one DDS participant). *out is NULL on failure. */
HAPTICD_C_API hapticd_status hapticd_client_create(const hapticd_client_options* options, hapticd_client** out);
/* Ends it: its claims end with it (the server sees the participant go). NULL is ignored. Destroying a client twice,
 * or calling anything with a destroyed one, is undefined behaviour (as free() twice is): set your pointer to NULL. */
HAPTICD_C_API void hapticd_client_destroy(hapticd_client* client);

/* ---- devices ---- */
/* The descriptions received so far: up to capacity into out, the number there are into *count. */
HAPTICD_C_API hapticd_status hapticd_list_devices(hapticd_client* client, hapticd_device_info* out, int32_t capacity,
                                                  int32_t* count);
/* Waits for the device's description (started != 0: one that carries the start pose). */
HAPTICD_C_API hapticd_status hapticd_wait_for_device(hapticd_client* client, const char* device, double timeout_s,
                                                     int32_t started, hapticd_device_info* out);
/* The newest state (HAPTICD_ERROR_NOT_FOUND before the first). Allocates nothing. */
HAPTICD_C_API hapticd_status hapticd_latest_state(hapticd_client* client, const char* device,
                                                  hapticd_device_state* out);
/* Waits for a state with serial > after. */
HAPTICD_C_API hapticd_status hapticd_wait_for_state(hapticd_client* client, const char* device, double timeout_s,
                                                    uint64_t after, hapticd_device_state* out);

/* ---- groups ---- */
HAPTICD_C_API hapticd_status hapticd_list_groups(hapticd_client* client, hapticd_group_info* out, int32_t capacity,
                                                 int32_t* count);
HAPTICD_C_API hapticd_status hapticd_wait_for_group(hapticd_client* client, const char* group, double timeout_s,
                                                    hapticd_group_info* out);
HAPTICD_C_API hapticd_status hapticd_latest_group_state(hapticd_client* client, const char* group,
                                                        hapticd_group_state* out);
HAPTICD_C_API hapticd_status hapticd_wait_for_group_state(hapticd_client* client, const char* group, double timeout_s,
                                                          uint64_t after, hapticd_group_state* out);

/* ---- events, telemetry, fault reports ---- */
/* The events received since the last call, oldest first: up to capacity into out (the rest stay for the next
 * call), the number taken into *count. */
HAPTICD_C_API hapticd_status hapticd_take_events(hapticd_client* client, hapticd_event* out, int32_t capacity,
                                                 int32_t* count);
HAPTICD_C_API hapticd_status hapticd_latest_telemetry(hapticd_client* client, const char* device,
                                                      hapticd_telemetry* out);
HAPTICD_C_API hapticd_status hapticd_latest_fault_report(hapticd_client* client, const char* device,
                                                         hapticd_fault_report* out);

/* ---- callbacks (NULL removes; replacing is atomic: once the call returns the old one is not called again) ---- */
/* Every state, on the DDS receive thread, one at a time: answer it there. */
typedef void (*hapticd_state_callback)(const hapticd_device_state* state, void* user);
HAPTICD_C_API hapticd_status hapticd_on_state(hapticd_client* client, hapticd_state_callback callback, void* user);
/* Every event, on the client's thread (events are also kept for hapticd_take_events). */
typedef void (*hapticd_event_callback)(const hapticd_event* event, void* user);
HAPTICD_C_API hapticd_status hapticd_on_event(hapticd_client* client, hapticd_event_callback callback, void* user);
/* A claim of this client ended without its release (the server handed the device on or freed it), once per claim,
 * on the DDS receive thread. Claim again or stop. */
typedef void (*hapticd_claim_lost_callback)(const char* device, const char* reason, void* user);
HAPTICD_C_API hapticd_status hapticd_on_claim_lost(hapticd_client* client, hapticd_claim_lost_callback callback,
                                                   void* user);
/* 1 when the newest claim of the device (or its group) was lost so, else 0. */
HAPTICD_C_API int32_t hapticd_claim_lost(hapticd_client* client, const char* device);

/* ---- requests: HAPTICD_OK when accepted, HAPTICD_ERROR_REFUSED when refused, HAPTICD_ERROR_TIMEOUT without a
 * reply; reply (may be NULL) receives the reply whatever the status. A request without a reply is sent again
 * with the same id every 250 ms until the timeout; the server applies it once. ---- */
HAPTICD_C_API hapticd_status hapticd_claim(hapticd_client* client, const char* device, double timeout_s,
                                           hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_release(hapticd_client* client, const char* device, double timeout_s,
                                             hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_switch_scheme(hapticd_client* client, const char* device, const char* scheme,
                                                   double timeout_s, hapticd_reply* reply);
/* parameter: "<stage>.<name>", e.g. "virtual_model.coupling_stiffness_n_per_m". */
HAPTICD_C_API hapticd_status hapticd_set_parameter(hapticd_client* client, const char* device, const char* parameter,
                                                   const double* values, int32_t value_count, double timeout_s,
                                                   hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_get_parameter(hapticd_client* client, const char* device, const char* parameter,
                                                   double timeout_s, hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_describe_parameter(hapticd_client* client, const char* device,
                                                        const char* parameter, double timeout_s,
                                                        hapticd_parameter_info* out, hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_emergency_stop(hapticd_client* client, const char* device, double timeout_s,
                                                    hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_recover(hapticd_client* client, const char* device, double timeout_s,
                                             hapticd_reply* reply);
/* Simulated devices: "push" {fx, fy, fz[, ramp_s]}, "move" {dx, dy, dz[, duration_s]}, "grasp" {g}, "release". */
HAPTICD_C_API hapticd_status hapticd_operator_command(hapticd_client* client, const char* device, const char* command,
                                                      const double* values, int32_t value_count, double timeout_s,
                                                      hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_claim_group(hapticd_client* client, const char* group, double timeout_s,
                                                 hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_release_group(hapticd_client* client, const char* group, double timeout_s,
                                                   hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_emergency_stop_group(hapticd_client* client, const char* group, double timeout_s,
                                                          hapticd_reply* reply);
HAPTICD_C_API hapticd_status hapticd_recover_group(hapticd_client* client, const char* group, double timeout_s,
                                                   hapticd_reply* reply);

/* ---- engine commands (after a claim). Each is copied into its target's slot and written to DDS by the
 * library's sender thread (Cyclone allocates when it writes; the caller's thread does not): no allocation, no
 * wait. The newest command of a target is written; a write that failed (DDS Security refusing this identity) is
 * told by the next send to that target as HAPTICD_ERROR_DDS. Up to 16 devices and groups per client. ---- */
HAPTICD_C_API hapticd_status hapticd_send(hapticd_client* client, const char* device, const hapticd_command* command);
HAPTICD_C_API hapticd_status hapticd_send_coupling(hapticd_client* client, const char* device,
                                                   const hapticd_pose* proxy, const hapticd_twist* proxy_twist,
                                                   uint64_t state_serial);
/* local_model may be NULL. */
HAPTICD_C_API hapticd_status hapticd_send_wrench(hapticd_client* client, const char* device,
                                                 const hapticd_wrench* wrench, const hapticd_local_model* local_model,
                                                 uint64_t state_serial);
HAPTICD_C_API hapticd_status hapticd_send_motion(hapticd_client* client, const char* device, const hapticd_pose* pose,
                                                 const hapticd_twist* twist, uint64_t state_serial);
/* One command per device of the group (after hapticd_claim_group), each naming its device, in the group's order. */
HAPTICD_C_API hapticd_status hapticd_send_group(hapticd_client* client, const char* group,
                                                const hapticd_command* commands, int32_t count);

/* ---- the engine helper (docs/engines.md, "The engine helper"; the C++ library's hapticd::client::Engine): finds
 * its device or group and waits until it started, claims it, answers each state through one callback, retakes a
 * claim the server ended, hands parameter events to a hook, ends on hapticd_engine_stop, a duration, the session's
 * end or a silent server (or waits for the server to come back and claims again), releases, says why. Commands go
 * out through the client's sender thread, as hapticd_send's. ---- */
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
 * soon as it came; answered_then: hapticd_engine_answered when it arrived. */
typedef void (*hapticd_engine_parameter_hook)(const hapticd_event* event, uint64_t answered_then, void* user);

/* The client must outlive the engine. options->size must be at least the size of this version's struct. */
HAPTICD_C_API hapticd_status hapticd_engine_create(hapticd_client* client, const hapticd_engine_options* options,
                                                   hapticd_engine** out);
HAPTICD_C_API void hapticd_engine_destroy(hapticd_engine* engine);
/* Finds the device or group and waits until it started; HAPTICD_ERROR_NOT_FOUND (said why) if it did not. */
HAPTICD_C_API hapticd_status hapticd_engine_connect(hapticd_engine* engine);
/* After hapticd_engine_connect: how many devices it answers for, and each one's description (with its start pose). */
HAPTICD_C_API int32_t hapticd_engine_device_count(hapticd_engine* engine);
HAPTICD_C_API hapticd_status hapticd_engine_device(hapticd_engine* engine, int32_t index, hapticd_device_info* out);
/* Hooks, each optional; set them before hapticd_engine_run. */
HAPTICD_C_API hapticd_status hapticd_engine_on_claim(hapticd_engine* engine, hapticd_engine_claim_hook hook,
                                                     void* user);
HAPTICD_C_API hapticd_status hapticd_engine_on_chores(hapticd_engine* engine, hapticd_engine_chores_hook hook,
                                                      void* user);
HAPTICD_C_API hapticd_status hapticd_engine_on_parameter(hapticd_engine* engine, hapticd_engine_parameter_hook hook,
                                                         void* user);
/* Connects (unless done), claims, answers until it ends, releases; end (may be NULL) says why. For the run it takes
 * the client's state and event callbacks (hapticd_on_state, hapticd_on_event) and clears them when it ends. HAPTICD_OK
 * whatever the reason (end->exit_code tells success); an error status only for a bad argument or a second run. */
HAPTICD_C_API hapticd_status hapticd_engine_run(hapticd_engine* engine, hapticd_engine_answer answer, void* user,
                                                hapticd_engine_end* end);
/* Ends the run at its next chore (any thread; not from a signal handler - set a flag and stop from the program). */
HAPTICD_C_API hapticd_status hapticd_engine_stop(hapticd_engine* engine);
HAPTICD_C_API uint64_t hapticd_engine_answered(hapticd_engine* engine);

#ifdef __cplusplus
}
#endif

#endif /* HAPTICD_CLIENT_H */
