/* A rendering engine in plain C on hapticd's C API (hapticd/client.h): a wall normal to x, 2 cm ahead of where
 * the handle starts, rendered through the server's virtual coupling. The engine helper (hapticd_engine_*) claims
 * the device, calls answer() for every state on the DDS receive thread - the proxy: the handle's pose, held back
 * at the wall - sends it, claims again when the server ended the claim (this process was stopped beyond the
 * server's claim hold; exit 3 when another client took the device meanwhile), and releases at the end.
 *   hapticd-c-wall-engine [--domain D] [--device NAME] [--id ID] [--duration S] [--push N] [--wait S]
 * --push asks the simulated operator to push with N newtons along +x once the device is claimed; --wait is how
 * long to wait for the device to start (20 s). SIGINT or SIGTERM ends the run as the duration does (the handler
 * only sets a flag; the helper's chores hook, every 20 ms, reads it).
 * Built against the installed package: cc -std=c11 wall_engine.c $(pkg-config --cflags --libs hapticd-client) */
#include <hapticd/client.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct wall_engine {
  hapticd_client* client;
  const char* device;
  double wall_x;
  double push_n;
} wall_engine;

static volatile sig_atomic_t stop_requested = 0;
static void request_stop(int signal_number) {
  (void)signal_number;
  stop_requested = 1;
}

/* Every 20 ms on the thread that runs the engine: a signal asked it to end (a stop, not a failure: the run says
 * HAPTICD_ENGINE_STOPPED and releases the device). */
static int32_t chores(void* user) {
  if (stop_requested) hapticd_engine_stop((hapticd_engine*)user);
  return 1;
}

/* The DDS receive thread, once per state: the proxy, held back at the wall, answers it. */
static int32_t answer(const hapticd_device_state* states, int32_t count, hapticd_command* commands, void* user) {
  const wall_engine* w = (const wall_engine*)user;
  (void)count;
  commands[0].kind = HAPTICD_COMMAND_COUPLING;
  commands[0].pose = states[0].pose;
  if (commands[0].pose.position.x > w->wall_x) commands[0].pose.position.x = w->wall_x;
  return 1; /* send it (the helper sets the state's serial) */
}

/* After each claim, on the thread that runs the engine: the first one says so and starts the operator's push. */
static int32_t claimed(int32_t again, void* user) {
  const wall_engine* w = (const wall_engine*)user;
  if (again) return 1;
  printf("c-wall-engine: claimed '%s'; a wall at x = %+.4f m\n", w->device, w->wall_x);
  fflush(stdout);
  if (w->push_n != 0.0) {
    const double push[4] = {w->push_n, 0.0, 0.0, 0.2};
    hapticd_reply reply;
    if (hapticd_client_operator_command(w->client, w->device, "push", push, 4, 5.0, &reply) != HAPTICD_OK)
      fprintf(stderr, "c-wall-engine: the push was not taken: %s\n", hapticd_last_error());
  }
  return 1;
}

int main(int argc, char** argv) {
  hapticd_client_options options = {.size = sizeof(hapticd_client_options), .client_id = "c-wall-engine"};
  hapticd_engine_options engine_options = {.size = sizeof(hapticd_engine_options),
                                           .name = "c-wall-engine",
                                           .device = "vishard3",
                                           .wait_s = 20.0,
                                           .duration_s = 10.0};
  wall_engine w = {.device = "vishard3"};
  for (int i = 1; i + 1 < argc; i += 2) {
    if (strcmp(argv[i], "--domain") == 0)
      options.domain_id = atoi(argv[i + 1]);
    else if (strcmp(argv[i], "--device") == 0)
      w.device = engine_options.device = argv[i + 1];
    else if (strcmp(argv[i], "--id") == 0)
      options.client_id = argv[i + 1];
    else if (strcmp(argv[i], "--duration") == 0)
      engine_options.duration_s = atof(argv[i + 1]);
    else if (strcmp(argv[i], "--push") == 0)
      w.push_n = atof(argv[i + 1]);
    else if (strcmp(argv[i], "--wait") == 0)
      engine_options.wait_s = atof(argv[i + 1]);
    else {
      fprintf(stderr, "c-wall-engine: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  if (hapticd_api_version() != HAPTICD_C_API_VERSION) {
    fprintf(stderr, "c-wall-engine: built for API %d, the library is %d\n", HAPTICD_C_API_VERSION,
            hapticd_api_version());
    return 2;
  }
  hapticd_engine* engine = NULL;
  if (hapticd_client_create(&options, &w.client) != HAPTICD_OK ||
      hapticd_engine_create(w.client, &engine_options, &engine) != HAPTICD_OK) {
    fprintf(stderr, "c-wall-engine: %s\n", hapticd_last_error());
    hapticd_client_destroy(w.client);
    return 2;
  }
  hapticd_device_info device;
  if (hapticd_engine_connect(engine) != HAPTICD_OK || hapticd_engine_device(engine, 0, &device) != HAPTICD_OK) {
    hapticd_engine_destroy(engine); /* the helper said why */
    hapticd_client_destroy(w.client);
    return 1;
  }
  const double start_x = device.start_pose.position.x;
  w.wall_x = start_x + 0.02;
  hapticd_engine_on_claim(engine, claimed, &w);
  hapticd_engine_on_chores(engine, chores, engine);
  signal(SIGINT, request_stop);
  signal(SIGTERM, request_stop);
  hapticd_engine_end end;
  hapticd_engine_run(engine, answer, &w, &end);
  hapticd_device_state last;
  const int have_last = hapticd_client_latest_state(w.client, w.device, &last) == HAPTICD_OK;
  uint64_t answered_states = 0;
  hapticd_engine_answered(engine, &answered_states);
  const unsigned long long answered = (unsigned long long)answered_states;
  printf("c-wall-engine: answered %llu states; handle %.4f m past the start, the wall at 0.0200 m\n", answered,
         have_last ? last.pose.position.x - start_x : 0.0);
  hapticd_engine_destroy(engine);
  hapticd_client_destroy(w.client);
  return end.exit_code != 0 ? end.exit_code : (answered > 0 ? 0 : 1);
}
