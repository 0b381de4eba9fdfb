/* Prints the C API's struct layouts (sizes of every struct, offsets of the fields of the structs a binding maps
 * field by field), one "name value" per line: the ABI test compares them with the committed
 * clients/c/abi/hapticd_c.layout, and the C# bindings' test its own struct sizes with the same file. */
#include <hapticd/client.h>
#include <stddef.h>
#include <stdio.h>

#define SIZE(T) printf("sizeof %s %zu\n", #T, sizeof(T))
#define OFFSET(T, F) printf("offsetof %s.%s %zu\n", #T, #F, offsetof(T, F))

int main(void) {
  SIZE(hapticd_vec3);
  SIZE(hapticd_quat);
  SIZE(hapticd_pose);
  SIZE(hapticd_twist);
  SIZE(hapticd_wrench);
  SIZE(hapticd_loop_summary);
  SIZE(hapticd_device_state);
  SIZE(hapticd_scheme_info);
  SIZE(hapticd_device_info);
  SIZE(hapticd_group_info);
  SIZE(hapticd_group_state);
  SIZE(hapticd_event);
  SIZE(hapticd_telemetry);
  SIZE(hapticd_fault_cycle);
  SIZE(hapticd_fault_report);
  SIZE(hapticd_reply);
  SIZE(hapticd_parameter_info);
  SIZE(hapticd_local_model);
  SIZE(hapticd_command);
  SIZE(hapticd_client_options);
  SIZE(hapticd_engine_options);
  SIZE(hapticd_engine_end);
  OFFSET(hapticd_device_state, serial);
  OFFSET(hapticd_device_state, cycle);
  OFFSET(hapticd_device_state, loop_time_ns);
  OFFSET(hapticd_device_state, pose);
  OFFSET(hapticd_device_state, twist);
  OFFSET(hapticd_device_state, operator_wrench);
  OFFSET(hapticd_device_state, environment_wrench);
  OFFSET(hapticd_device_state, target_pose);
  OFFSET(hapticd_device_state, dof);
  OFFSET(hapticd_device_state, position);
  OFFSET(hapticd_device_state, velocity);
  OFFSET(hapticd_device_state, torque);
  OFFSET(hapticd_device_state, buttons);
  OFFSET(hapticd_device_state, gripper);
  OFFSET(hapticd_device_state, mode);
  OFFSET(hapticd_device_state, flags);
  OFFSET(hapticd_device_state, fault);
  OFFSET(hapticd_device_state, scheme);
  OFFSET(hapticd_device_state, owner);
  OFFSET(hapticd_device_state, engine_serial);
  OFFSET(hapticd_device_state, loop);
  OFFSET(hapticd_reply, accepted);
  OFFSET(hapticd_reply, message);
  OFFSET(hapticd_reply, value_count);
  OFFSET(hapticd_reply, values);
  OFFSET(hapticd_command, kind);
  OFFSET(hapticd_command, state_serial);
  OFFSET(hapticd_command, wrench);
  OFFSET(hapticd_command, has_local_model);
  OFFSET(hapticd_command, local_model);
  OFFSET(hapticd_command, pose);
  OFFSET(hapticd_command, twist);
  OFFSET(hapticd_client_options, domain_id);
  OFFSET(hapticd_client_options, cyclone_config);
  OFFSET(hapticd_client_options, network);
  OFFSET(hapticd_client_options, command_deadline_s);
  OFFSET(hapticd_engine_options, name);
  OFFSET(hapticd_engine_options, device);
  OFFSET(hapticd_engine_options, group);
  OFFSET(hapticd_engine_options, wait_s);
  OFFSET(hapticd_engine_options, server_timeout_s);
  OFFSET(hapticd_engine_options, duration_s);
  OFFSET(hapticd_engine_options, wait_for_server);
  OFFSET(hapticd_engine_end, exit_code);
  OFFSET(hapticd_engine_end, message);
  return hapticd_api_version() == HAPTICD_C_API_VERSION ? 0 : 1;
}
