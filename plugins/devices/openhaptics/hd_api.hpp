#pragma once
// The functions of 3D Systems' OpenHaptics HD API (libHD) the plugin uses, as function-pointer types with the
// prototypes of the vendor's published C headers (hd.h, hdDefines.h, hdScheduler.h; OpenHaptics 3.x), and the
// constants it needs with their values from hdDefines.h. Taken by name from the library loaded at run time
// (VendorLibrary): nothing of the vendor's is compiled in.
#include "vendor_library.hpp"

namespace hapticd::plugins::openhaptics {

using HHD = unsigned int;
using HDenum = unsigned int;
using HDerror = unsigned int;
using HDSchedulerHandle = unsigned long;
using HDCallbackCode = unsigned int;
using HDSchedulerCallback = HDCallbackCode (*)(void* user_data);

// HDErrorInfo, returned by value by hdGetError().
struct HDErrorInfo {
  HDerror errorCode;
  int internalErrorCode;
  HHD hHD;
};

// hdDefines.h
inline constexpr HDerror kSuccess = 0x0000;                      // HD_SUCCESS
inline constexpr HHD kInvalidHandle = 0xFFFFFFFF;                // HD_INVALID_HANDLE
inline constexpr HDenum kCurrentButtons = 0x2000;                // HD_CURRENT_BUTTONS
inline constexpr HDenum kCurrentPosition = 0x2050;               // HD_CURRENT_POSITION: 3 doubles, mm
inline constexpr HDenum kCurrentVelocity = 0x2051;               // HD_CURRENT_VELOCITY: mm/s
inline constexpr HDenum kCurrentTransform = 0x2052;              // HD_CURRENT_TRANSFORM: 16 doubles, column-major, mm
inline constexpr HDenum kCurrentAngularVelocity = 0x2053;        // HD_CURRENT_ANGULAR_VELOCITY: rad/s
inline constexpr HDenum kCurrentJointAngles = 0x2100;            // HD_CURRENT_JOINT_ANGLES: 3 doubles, rad
inline constexpr HDenum kCurrentGimbalAngles = 0x2150;           // HD_CURRENT_GIMBAL_ANGLES: 3 doubles, rad
inline constexpr HDenum kVersion = 0x2500;                       // HD_VERSION: the HD library's
inline constexpr HDenum kDeviceModelType = 0x2501;               // HD_DEVICE_MODEL_TYPE
inline constexpr HDenum kDeviceDriverVersion = 0x2502;           // HD_DEVICE_DRIVER_VERSION
inline constexpr HDenum kDeviceSerialNumber = 0x2504;            // HD_DEVICE_SERIAL_NUMBER
inline constexpr HDenum kUsableWorkspaceDimensions = 0x2551;     // 6 doubles, mm: min x y z, max x y z
inline constexpr HDenum kInputDof = 0x2553;                      // HD_INPUT_DOF
inline constexpr HDenum kOutputDof = 0x2554;                     // HD_OUTPUT_DOF
inline constexpr HDenum kCalibrationStyle = 0x2555;              // HD_CALIBRATION_STYLE
inline constexpr HDenum kNominalMaxStiffness = 0x2602;           // N/mm
inline constexpr HDenum kNominalMaxForce = 0x2603;               // N
inline constexpr HDenum kNominalMaxContinuousForce = 0x2604;     // N
inline constexpr HDenum kNominalMaxDamping = 0x2609;             // N s/mm
inline constexpr HDenum kNominalMaxTorqueStiffness = 0x2620;     // HD_NOMINAL_MAX_TORQUE_STIFFNESS: mN m/rad
inline constexpr HDenum kNominalMaxTorqueDamping = 0x2621;       // HD_NOMINAL_MAX_TORQUE_DAMPING: mN m s/rad
inline constexpr HDenum kNominalMaxTorqueForce = 0x2622;         // HD_NOMINAL_MAX_TORQUE_FORCE: mN m
inline constexpr HDenum kCurrentForce = 0x2700;                  // HD_CURRENT_FORCE: 3 doubles, N
inline constexpr HDenum kCurrentTorque = 0x2701;                 // HD_CURRENT_TORQUE: 3 doubles, mN m (6-DOF output)
inline constexpr HDenum kForceOutput = 0x4000;                   // HD_FORCE_OUTPUT
inline constexpr HDenum kCalibrationOk = 0x5000;                 // HD_CALIBRATION_OK
inline constexpr HDenum kCalibrationNeedsUpdate = 0x5001;        // HD_CALIBRATION_NEEDS_UPDATE
inline constexpr HDenum kCalibrationNeedsManualInput = 0x5002;   // HD_CALIBRATION_NEEDS_MANUAL_INPUT
inline constexpr int kCalibrationEncoderReset = 1 << 0;          // HD_CALIBRATION_ENCODER_RESET
inline constexpr int kCalibrationAuto = 1 << 1;                  // HD_CALIBRATION_AUTO
inline constexpr int kCalibrationInkwell = 1 << 2;               // HD_CALIBRATION_INKWELL
inline constexpr HDCallbackCode kCallbackDone = 0;               // HD_CALLBACK_DONE
inline constexpr HDCallbackCode kCallbackContinue = 1;           // HD_CALLBACK_CONTINUE
inline constexpr unsigned short kMaxSchedulerPriority = 0xFFFF;  // HD_MAX_SCHEDULER_PRIORITY (USHRT_MAX)

struct HdApi {
  HHD (*init_device)(const char* name);
  void (*disable_device)(HHD);
  void (*make_current_device)(HHD);
  void (*begin_frame)(HHD);
  void (*end_frame)(HHD);
  void (*get_integerv)(HDenum, int*);
  void (*get_doublev)(HDenum, double*);
  const char* (*get_string)(HDenum);
  void (*set_doublev)(HDenum, const double*);
  void (*enable)(HDenum);
  void (*disable)(HDenum);
  HDErrorInfo (*get_error)();
  const char* (*get_error_string)(HDerror);
  HDenum (*check_calibration)();
  void (*update_calibration)(HDenum style);
  void (*start_scheduler)();
  void (*stop_scheduler)();
  HDSchedulerHandle (*schedule_asynchronous)(HDSchedulerCallback, void* user_data, unsigned short priority);
  void (*unschedule)(HDSchedulerHandle);
  void (*set_scheduler_rate)(unsigned long rate_hz);

  // Takes every function from `library`; throws VendorLibraryError naming one that is missing.
  explicit HdApi(const VendorLibrary& library);
  // The SDK's text of an error code ("an error the SDK does not describe" when it has none).
  [[nodiscard]] const char* text_of(HDerror code) const noexcept;
};

}  // namespace hapticd::plugins::openhaptics
