#pragma once
// False alarms of lost detection on the real logs (kidnapped example, with --data): vdt-opt and
// vdt-ekf with the settings and map knowledge `vdtnav localize` uses, on
//  - intel-study: the Intel lab, map from the last third (corrected poses), the first two thirds
//    localized on the raw odometry (the Intel study);
//  - intel-odd-even and mit-killian-odd-even: map from the odd scans of a corrected log, the even
//    scans localized (odometry: the corrected poses; MIT's no-return code detected as the CLI
//    does).
// A scan is right when within 0.5 m of its corrected pose; a false alarm is a right scan reported
// lost. Writes false_alarms.csv (log,method,scans,right,flagged_lost,false_alarms,
// false_alarm_pct,off_0.5m,recoveries,ms_mean,ms_max,cpu_ms_max,ms_median,ms_p99; cpu: the
// slowest update's processor time; p99: nearest rank), false_alarms.md and per log
// <log>_agreement.png: each scan's explained fraction and the window's contradiction, with the
// lost flags.
#include <string>

namespace false_alarms {

/// Runs the logs found under `data` (skips those absent) and writes into `out`.
/// \return the number of logs run.
int run(const std::string& data, const std::string& out);

}  // namespace false_alarms
