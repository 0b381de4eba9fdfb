/* A minimal rendering engine in plain C, built from idl/hapticd_msg.idl alone (idlc's C types and Cyclone's
 * C API; none of hapticd's libraries). It claims a device, answers every state with a virtual floor 10 mm
 * below the start position (a WRENCH command with a local linear model the server evaluates at loop rate),
 * and releases the device after a number of states.
 *
 *   hapticd-minimal-c-engine CYCLONE_XML DEVICE [DOMAIN] [STATES]
 *
 * CYCLONE_XML: hapticd's loopback configuration (config/dds/cyclonedds-loopback.xml). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dds/dds.h"
#include "hapticd_msg.h"

static char* read_file(const char* path) {
  FILE* f = fopen(path, "rb");
  if (f == NULL) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char* text = malloc((size_t)n + 1);
  if (text != NULL && fread(text, 1, (size_t)n, f) == (size_t)n) text[n] = '\0';
  fclose(f);
  return text;
}

static void copy_name(char* out, const char* in) {
  strncpy(out, in, 31);
  out[31] = '\0';
}

static int request(dds_entity_t writer, dds_entity_t replies, const char* device, const char* client,
                   hapticd_msg_RequestKind kind, unsigned long long id) {
  hapticd_msg_ControlRequest r;
  memset(&r, 0, sizeof r);
  copy_name(r.device, device);
  copy_name(r.client, client);
  r.request_id = id;
  r.kind = kind;
  /* Sent again with the same id every 0.2 s without a reply, for up to 5 s: the server answers a repeated request
     again and applies it once (the first may reach it before discovery lets it answer us, or be lost on a loaded
     machine). */
  for (int tries = 0; tries < 500; ++tries) {
    if (tries % 20 == 0 && dds_write(writer, &r) != DDS_RETCODE_OK) return 0;
    hapticd_msg_ControlReply reply;
    void* samples[1] = {&reply};
    dds_sample_info_t info;
    while (dds_take(replies, samples, &info, 1, 1) > 0) {
      if (info.valid_data && reply.request_id == id && strcmp(reply.client, client) == 0) {
        printf("  request %llu: %s (%s)\n", id, reply.accepted ? "accepted" : "refused", reply.message);
        return reply.accepted;
      }
    }
    dds_sleepfor(DDS_MSECS(10));
  }
  printf("  request %llu: no reply\n", id);
  return 0;
}

int main(int argc, char** argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: %s CYCLONE_XML DEVICE [DOMAIN] [STATES]\n", argv[0]);
    return 2;
  }
  const char* device = argv[2];
  const dds_domainid_t domain = argc > 3 ? (dds_domainid_t)atoi(argv[3]) : 0;
  const long states_wanted = argc > 4 ? atol(argv[4]) : 2000;
  char* xml = read_file(argv[1]);
  if (xml == NULL) {
    fprintf(stderr, "cannot read %s\n", argv[1]);
    return 2;
  }
  const dds_entity_t dom = dds_create_domain(domain, xml);
  free(xml);
  const dds_entity_t participant = dds_create_participant(domain, NULL, NULL);
  if (dom < 0 || participant < 0) {
    fprintf(stderr, "cannot create the participant\n");
    return 1;
  }

  /* QoS as docs/dds-interface.md lists them. */
  dds_qos_t* best_effort = dds_create_qos();
  dds_qset_reliability(best_effort, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_history(best_effort, DDS_HISTORY_KEEP_LAST, 1);
  dds_qos_t* command_qos = dds_create_qos();
  dds_qset_reliability(command_qos, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_history(command_qos, DDS_HISTORY_KEEP_LAST, 1);
  dds_qset_deadline(command_qos, DDS_MSECS(50));
  dds_qset_liveliness(command_qos, DDS_LIVELINESS_AUTOMATIC, DDS_MSECS(500));
  dds_qos_t* reliable = dds_create_qos();
  dds_qset_reliability(reliable, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_history(reliable, DDS_HISTORY_KEEP_LAST, 32);

  const dds_entity_t state_topic =
      dds_create_topic(participant, &hapticd_msg_DeviceState_desc, "hapticd_state", best_effort, NULL);
  const dds_entity_t command_topic =
      dds_create_topic(participant, &hapticd_msg_EngineCommand_desc, "hapticd_command", command_qos, NULL);
  const dds_entity_t request_topic =
      dds_create_topic(participant, &hapticd_msg_ControlRequest_desc, "hapticd_request", reliable, NULL);
  const dds_entity_t reply_topic =
      dds_create_topic(participant, &hapticd_msg_ControlReply_desc, "hapticd_reply", reliable, NULL);
  const dds_entity_t states = dds_create_reader(participant, state_topic, best_effort, NULL);
  const dds_entity_t commands = dds_create_writer(participant, command_topic, command_qos, NULL);
  const dds_entity_t requests = dds_create_writer(participant, request_topic, reliable, NULL);
  const dds_entity_t replies = dds_create_reader(participant, reply_topic, reliable, NULL);
  dds_delete_qos(best_effort);
  dds_delete_qos(command_qos);
  dds_delete_qos(reliable);
  if (states < 0 || commands < 0 || requests < 0 || replies < 0) {
    fprintf(stderr, "cannot create the readers and writers\n");
    return 1;
  }

  /* Wait for the server both ways - its request reader matched to our writer and its reply writer to our
     reader (a reply written before the second match is lost) - then claim. */
  for (int i = 0; i < 500; ++i) {
    dds_publication_matched_status_t m;
    dds_subscription_matched_status_t r;
    if (dds_get_publication_matched_status(requests, &m) == DDS_RETCODE_OK && m.current_count > 0 &&
        dds_get_subscription_matched_status(replies, &r) == DDS_RETCODE_OK && r.current_count > 0) {
      break;
    }
    dds_sleepfor(DDS_MSECS(10));
  }
  const char* client = "minimal-c-engine";
  printf("minimal-c-engine: claiming '%s'\n", device);
  if (!request(requests, replies, device, client, hapticd_msg_REQUEST_CLAIM, 1)) return 1;

  const dds_entity_t waitset = dds_create_waitset(participant);
  const dds_entity_t readable = dds_create_readcondition(states, DDS_ANY_STATE);
  dds_waitset_attach(waitset, readable, 0);
  double floor_z = 0.0;
  int have_floor = 0;
  unsigned long long serial = 0;
  long answered = 0;
  double lowest = 1e9;
  while (answered < states_wanted) {
    if (dds_waitset_wait(waitset, NULL, 0, DDS_SECS(3)) <= 0) {
      printf("minimal-c-engine: no state for 3 s\n");
      break;
    }
    hapticd_msg_DeviceState s;
    void* samples[1] = {&s};
    dds_sample_info_t info;
    while (answered < states_wanted && dds_take(states, samples, &info, 1, 1) > 0) {
      if (!info.valid_data || strcmp(s.device, device) != 0) continue;
      if (!have_floor) {
        floor_z = s.handle_pose.position[2] - 0.01;
        have_floor = 1;
      }
      if (s.handle_pose.position[2] < lowest) lowest = s.handle_pose.position[2];
      hapticd_msg_EngineCommand c;
      memset(&c, 0, sizeof c);
      copy_name(c.device, device);
      copy_name(c.engine, client);
      c.serial = ++serial;
      c.state_serial = s.serial;
      c.kind = hapticd_msg_COMMAND_WRENCH;
      /* A floor: a one-sided spring, linearised about the floor height while the handle is below it. */
      if (s.handle_pose.position[2] < floor_z) {
        c.local_model = true;
        c.anchor.position[0] = s.handle_pose.position[0];
        c.anchor.position[1] = s.handle_pose.position[1];
        c.anchor.position[2] = floor_z;
        c.anchor.orientation[0] = 1.0;
        c.stiffness[2] = 3000.0;
        c.damping[2] = 20.0;
      }
      c.command_pose.orientation[0] = 1.0;
      dds_write(commands, &c);
      ++answered;
    }
  }
  printf("minimal-c-engine: answered %ld states; lowest handle height %.1f mm below the start\n", answered,
         have_floor ? 1e3 * (floor_z + 0.01 - lowest) : 0.0);
  request(requests, replies, device, client, hapticd_msg_REQUEST_RELEASE, 2);
  dds_delete(participant);
  dds_delete(dom);
  return answered > 0 ? 0 : 1;
}
