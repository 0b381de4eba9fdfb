/* Preloaded into `ddsperf ping` by bench/dds_round_trip.py to find out what ddsperf's latency figures are:
 * every dds_write_ts the process makes gets its source timestamp moved HAPTICD_DDSPERF_SHIFT_NS into the past.
 * ddsperf measures a ping's latency from that timestamp (its pong echoes it), so the figures it prints grow by
 * the shift if they are round trips, by half of it if they are half round trips. The shift is kept even:
 * ddsperf marks pings by the timestamp's lowest bit. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdint.h>
#include <stdlib.h>

typedef int32_t entity_t;
typedef int32_t return_t;
typedef int64_t time_ns_t;

return_t dds_write_ts(entity_t writer, const void* data, time_ns_t timestamp);

return_t dds_write_ts(entity_t writer, const void* data, time_ns_t timestamp) {
  static return_t (*next)(entity_t, const void*, time_ns_t);
  static time_ns_t shift = -1;
  if (next == NULL) next = (return_t(*)(entity_t, const void*, time_ns_t))dlsym(RTLD_NEXT, "dds_write_ts");
  if (shift < 0) {
    const char* text = getenv("HAPTICD_DDSPERF_SHIFT_NS");
    shift = text != NULL ? (strtoll(text, NULL, 10) & ~(time_ns_t)1) : 0;
  }
  return next(writer, data, timestamp - shift);
}
