#include "hd_api.hpp"

namespace hapticd::plugins::openhaptics {

HdApi::HdApi(const VendorLibrary& l)
    : init_device(l.function<decltype(init_device)>("hdInitDevice")),
      disable_device(l.function<decltype(disable_device)>("hdDisableDevice")),
      make_current_device(l.function<decltype(make_current_device)>("hdMakeCurrentDevice")),
      begin_frame(l.function<decltype(begin_frame)>("hdBeginFrame")),
      end_frame(l.function<decltype(end_frame)>("hdEndFrame")),
      get_integerv(l.function<decltype(get_integerv)>("hdGetIntegerv")),
      get_doublev(l.function<decltype(get_doublev)>("hdGetDoublev")),
      get_string(l.function<decltype(get_string)>("hdGetString")),
      set_doublev(l.function<decltype(set_doublev)>("hdSetDoublev")),
      enable(l.function<decltype(enable)>("hdEnable")),
      disable(l.function<decltype(disable)>("hdDisable")),
      get_error(l.function<decltype(get_error)>("hdGetError")),
      get_error_string(l.function<decltype(get_error_string)>("hdGetErrorString")),
      check_calibration(l.function<decltype(check_calibration)>("hdCheckCalibration")),
      update_calibration(l.function<decltype(update_calibration)>("hdUpdateCalibration")),
      start_scheduler(l.function<decltype(start_scheduler)>("hdStartScheduler")),
      stop_scheduler(l.function<decltype(stop_scheduler)>("hdStopScheduler")),
      schedule_asynchronous(l.function<decltype(schedule_asynchronous)>("hdScheduleAsynchronous")),
      unschedule(l.function<decltype(unschedule)>("hdUnschedule")),
      set_scheduler_rate(l.function<decltype(set_scheduler_rate)>("hdSetSchedulerRate")) {}

const char* HdApi::text_of(HDerror code) const noexcept {
  const char* text = get_error_string(code);
  return text != nullptr ? text : "an error the SDK does not describe";
}

}  // namespace hapticd::plugins::openhaptics
