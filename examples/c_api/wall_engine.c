/* A rendering engine in plain C on hapticd's C API (hapticd/client.h): a wall normal to x, 2 cm ahead of where
 * the handle starts, rendered through the server's virtual coupling. Every state is answered from the state
 * callback (the DDS receive thread) with the proxy: the handle's pose, held back at the wall. A claim the server
 * ends (this process was stopped beyond the server's claim hold) is told by the claim-lost callback: the engine
 * claims again, or exits 3 when another client holds the device.
 *   hapticd-c-wall-engine [--domain D] [--device NAME] [--id ID] [--duration S] [--push N] [--wait S]
 * --push asks the simulated operator to push with N newtons along +x once the device is claimed; --wait is how
 * long to wait for the device's first state (20 s).
 * Built against the installed package: cc -std=c11 wall_engine.c $(pkg-config --cflags --libs hapticd-client) */
#define _POSIX_C_SOURCE 200809L /* nanosleep, clock_gettime */
#include <hapticd/client.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char* g_device = "vishard3";
static double g_wall_x = 0.0;
static atomic_ullong g_answered;
static atomic_int g_claim_lost;
static hapticd_client* g_client = NULL;

/* The DDS receive thread, once per state: the proxy, held back at the wall, answers it. */
static void on_state(const hapticd_device_state* s, void* user) {
  (void)user;
  if (strcmp(s->device, g_device) != 0) return;
  hapticd_pose proxy = s->pose;
  if (proxy.position.x > g_wall_x) proxy.position.x = g_wall_x;
  const hapticd_twist still = {{0, 0, 0}, {0, 0, 0}};
  if (hapticd_send_coupling(g_client, g_device, &proxy, &still, s->serial) == HAPTICD_OK)
    atomic_fetch_add(&g_answered, 1);
}

/* The receive thread, once per claim the server ended: noted for the main loop (a callback must not wait). */
static void on_claim_lost(const char* device, const char* reason, void* user) {
  (void)user;
  printf("c-wall-engine: the server ended the claim of '%s': %s\n", device, reason);
  fflush(stdout);
  atomic_store(&g_claim_lost, 1);
}

static void sleep_s(double seconds) {
  struct timespec t;
  t.tv_sec = (time_t)seconds;
  t.tv_nsec = (long)((seconds - (double)t.tv_sec) * 1e9);
  nanosleep(&t, NULL);
}

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char** argv) {
  hapticd_client_options options = {"c-wall-engine", 0, NULL, NULL, 0.0};
  double duration_s = 10.0, push_n = 0.0, wait_s = 20.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (strcmp(argv[i], "--domain") == 0)
      options.domain_id = atoi(argv[i + 1]);
    else if (strcmp(argv[i], "--device") == 0)
      g_device = argv[i + 1];
    else if (strcmp(argv[i], "--id") == 0)
      options.client_id = argv[i + 1];
    else if (strcmp(argv[i], "--duration") == 0)
      duration_s = atof(argv[i + 1]);
    else if (strcmp(argv[i], "--push") == 0)
      push_n = atof(argv[i + 1]);
    else if (strcmp(argv[i], "--wait") == 0)
      wait_s = atof(argv[i + 1]);
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
  if (hapticd_client_create(&options, &g_client) != HAPTICD_OK) {
    fprintf(stderr, "c-wall-engine: %s\n", hapticd_last_error());
    return 2;
  }
  int code = 0;
  hapticd_device_state first;
  hapticd_reply reply;
  if (hapticd_wait_for_state(g_client, g_device, wait_s, 0, &first) != HAPTICD_OK) {
    fprintf(stderr, "c-wall-engine: no state from '%s': %s\n", g_device, hapticd_last_error());
    hapticd_client_destroy(g_client);
    return 1;
  }
  const double start_x = first.pose.position.x;
  g_wall_x = start_x + 0.02;
  if (hapticd_claim(g_client, g_device, 5.0, &reply) != HAPTICD_OK) {
    fprintf(stderr, "c-wall-engine: cannot claim '%s': %s\n", g_device, hapticd_last_error());
    hapticd_client_destroy(g_client);
    return 1;
  }
  hapticd_on_claim_lost(g_client, on_claim_lost, NULL);
  hapticd_on_state(g_client, on_state, NULL);
  printf("c-wall-engine: claimed '%s'; a wall at x = %+.4f m\n", g_device, g_wall_x);
  fflush(stdout);
  if (push_n != 0.0) {
    const double push[4] = {push_n, 0.0, 0.0, 0.2};
    if (hapticd_operator_command(g_client, g_device, "push", push, 4, 5.0, &reply) != HAPTICD_OK)
      fprintf(stderr, "c-wall-engine: the push was not taken: %s\n", hapticd_last_error());
  }
  const double end = now_s() + duration_s;
  while (now_s() < end) {
    sleep_s(0.05);
    if (atomic_exchange(&g_claim_lost, 0)) {
      if (hapticd_claim(g_client, g_device, 5.0, &reply) == HAPTICD_OK) {
        printf("c-wall-engine: claimed '%s' again\n", g_device);
        fflush(stdout);
      } else {
        fprintf(stderr, "c-wall-engine: cannot claim '%s' again: %s\n", g_device, hapticd_last_error());
        code = 3;
        break;
      }
    }
  }
  hapticd_on_state(g_client, NULL, NULL);
  hapticd_device_state last;
  const int have_last = hapticd_latest_state(g_client, g_device, &last) == HAPTICD_OK;
  hapticd_release(g_client, g_device, 1.0, &reply);
  printf("c-wall-engine: answered %llu states; handle %.4f m past the start, the wall at 0.0200 m\n",
         (unsigned long long)atomic_load(&g_answered), have_last ? last.pose.position.x - start_x : 0.0);
  hapticd_client_destroy(g_client);
  return code != 0 ? code : (atomic_load(&g_answered) > 0 ? 0 : 1);
}
