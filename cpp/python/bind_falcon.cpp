// SPDX-License-Identifier: GPL-3.0-or-later
// hapticfluid._core Falcon: list_falcons, open_falcon, open_simulated_falcon, FalconDevice.
// Argument conversion, docstrings and GIL release only.
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "haptics/devices/device.h"
#include "haptics/devices/device_claim.h"
#include "haptics/falcon/falcon.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/named_args.h"

namespace py = pybind11;

namespace hf::python {
namespace {

using haptics::Device;
using haptics::DevicePtr;
using haptics::falcon::FalconDevice;
using haptics::falcon::FalconOptions;

FalconOptions falconOptions(bool home, double homing_timeout, float max_force) {
  FalconOptions o;
  o.home = home;
  o.homingTimeout_s = homing_timeout;
  o.maxForce_n = max_force;
  return o;
}

py::dict statsDict(const haptics::falcon::FalconStats& s) {
  py::dict d;
  d["packets"] = s.packets;
  d["missed_replies"] = s.missedReplies;
  d["force_clamps"] = s.forceClamps;
  d["command_clamps"] = s.commandClamps;
  d["forward_failures"] = s.forwardFailures;
  d["upload_attempts"] = s.uploadAttempts;
  d["firmware_uploaded"] = s.firmwareUploaded;
  return d;
}

}  // namespace

void addFalcon(py::module_& m) {
  // Device, DeviceInfo and DeviceState are registered by addHaptics, which runs first.

  py::class_<FalconDevice, Device, std::shared_ptr<FalconDevice>> falcon(
      m, "FalconDevice",
      "A Novint Falcon (or the simulated one) driven over USB; made by open_falcon() or\n"
      "open_simulated_falcon(). Each read() is one packet exchange; a force from write_force()\n"
      "goes out with the next read(), and only once the Falcon is homed.");
  falcon.def("stats", [](const FalconDevice& d) { return statsDict(d.stats()); },
             "Counters: packets, missed_replies, force_clamps (above max_force), command_clamps (int16),\n"
             "forward_failures, upload_attempts, firmware_uploaded.");
  defNamed(
          falcon, "home",
          [](FalconDevice& d, double timeout) {
            const haptics::DeviceClaim claim(d, "home() it");
            d.home(timeout);
          },
          py::arg("timeout") = 60.0, py::call_guard<py::gil_scoped_release>(),
           "Exchange packets until homed (red LED: pull the grip all the way out, push it in; green:\n"
           "homed). timeout in s; raises HapticFluidError with instructions when it passes, or while\n"
           "a HapticSession drives the device.");

  defNamed(
      m, "list_falcons",
      [](bool probe_firmware) {
        std::vector<haptics::falcon::FalconListing> found;
        {
          py::gil_scoped_release release;
          found = haptics::falcon::listFalcons(probe_firmware);
        }
        py::list out;
        for (const auto& f : found) {
          py::dict d;
          d["index"] = f.index;
          d["bus"] = f.bus;
          d["address"] = f.address;
          d["serial"] = f.serial;
          d["permission_ok"] = f.permissionOk;
          d["firmware_loaded"] = f.firmwareLoaded;
          d["problem"] = f.problem;
          out.append(d);
        }
        return out;
      },
      py::arg("probe_firmware") = true,
      "The Novint Falcons plugged in (USB 0403:cb48), one dict each: index (for open_falcon),\n"
      "bus, address, serial ('' if unknown), permission_ok (False: install the udev rule, see\n"
      "falcon_udev_rule()), firmware_loaded (True/False, None if not checked), problem ('' or what\n"
      "is wrong and what to do). probe_firmware opens each one and exchanges a few zero-force\n"
      "packets. None plugged in: an empty list.");
  m.def("falcon_udev_rule", &haptics::falcon::udevRule,
        "The udev rule that lets a logged-in user open the Falcon, and how to install it.");
  defNamed(
      m, "open_falcon",
      [](std::optional<std::string> firmware, int index, bool home, double homing_timeout,
         float max_force) -> DevicePtr {
        py::gil_scoped_release release;
        FalconOptions o = falconOptions(home, homing_timeout, max_force);
        if (firmware) o.firmware = haptics::falcon::readFirmwareFile(*firmware);
        return haptics::falcon::openFalcon(index, std::move(o));
      },
      py::arg("firmware") = py::none(), py::arg("index") = 0, py::arg("home") = true, py::arg("homing_timeout") = 60.0,
      py::arg("max_force") = 8.0f,
      "Open Falcon number `index` of list_falcons() and return a FalconDevice.\n"
      "firmware: path of the Falcon firmware .bin (Novint's, e.g. nvent_firmware.bin; not shipped),\n"
      "  uploaded when the Falcon is not running firmware (after every power-on); None: it must be.\n"
      "home: wait until the user has homed it (LED red: pull the grip all the way out and push it\n"
      "  in; green: homed), at most homing_timeout s. Without homing no force is applied.\n"
      "max_force: the device never commands more (N, at most 8 for the Falcon's profile).\n"
      "Raises HapticFluidError when none is plugged in, on a permission problem (with the udev\n"
      "rule), or when the firmware upload or homing fails.");
  defNamed(
      m, "open_simulated_falcon",
      [](std::optional<py::bytes> firmware_bytes, bool home, double homing_timeout, float max_force,
         double hand_mass, double hand_stiffness, double hand_damping, std::optional<long> unplug_after,
         std::optional<std::vector<std::array<double, 4>>> hand_path, bool hand_loop,
         std::optional<double> hand_stiffness_homed) -> DevicePtr {
        haptics::falcon::SimulatedFalconOptions sim;
        if (hand_path) {
          std::vector<haptics::falcon::HandWaypoint> waypoints;
          for (const auto& r : *hand_path) waypoints.push_back({r[0], glm::dvec3(r[1], r[2], r[3])});
          sim.handPath = haptics::falcon::scriptedHand(std::move(waypoints), hand_loop);
        }
        FalconOptions o = falconOptions(home, homing_timeout, max_force);
        if (firmware_bytes) {
          const std::string bytes = *firmware_bytes;
          if (bytes.empty()) throw InvalidArgument("firmware_bytes is empty: pass None (firmware running) or the image");
          sim.expectedFirmware.assign(bytes.begin(), bytes.end());
          o.firmware = sim.expectedFirmware;
        }
        sim.handMass_kg = hand_mass;
        sim.handStiffness_n_m = hand_stiffness;
        sim.handDamping_n_s_m = hand_damping;
        if (hand_stiffness_homed) {
          if (!std::isfinite(*hand_stiffness_homed) || *hand_stiffness_homed < 0.0) {
            throw InvalidArgument("hand_stiffness_homed must be a finite number of N/m >= 0, or None");
          }
          sim.handStiffnessHomed_n_m = *hand_stiffness_homed;
        }
        if (unplug_after) {
          if (*unplug_after < 1) throw InvalidArgument("unplug_after must be at least 1 packet, or None");
          sim.faults.unplugAtPacket = *unplug_after;
        }
        py::gil_scoped_release release;
        auto transport = std::make_shared<haptics::falcon::SimulatedFalconTransport>(std::move(sim));
        return haptics::falcon::openSimulatedFalcon(transport, std::move(o));
      },
      py::arg("firmware_bytes") = py::none(), py::arg("home") = true, py::arg("homing_timeout") = 10.0,
      py::arg("max_force") = 8.0f, py::arg("hand_mass") = 0.15, py::arg("hand_stiffness") = 300.0,
      py::arg("hand_damping") = 12.0, py::arg("unplug_after") = py::none(), py::arg("hand_path") = py::none(),
      py::arg("hand_loop") = false, py::arg("hand_stiffness_homed") = py::none(),
      "The whole Falcon driver on a simulated Falcon (no hardware): a FalconDevice.\n"
      "firmware_bytes: None: the firmware is already running; bytes: the simulated DSP waits in its\n"
      "  bootloader and the driver uploads these bytes, echo-checked, as for a real Falcon.\n"
      "home: the simulated user homes it at once (pulls the grip out and pushes it in, 0.6 s of\n"
      "  simulated time); homing_timeout in s.\n"
      "hand_mass (kg), hand_stiffness (N/m), hand_damping (N s/m): the hand holding the grip at the\n"
      "  workspace centre; a force F moves it about F / hand_stiffness. Simulated time advances\n"
      "  1 ms per read(). max_force in N.\n"
      "unplug_after: the simulated cable is pulled after this many packets (homing takes ~200):\n"
      "  read() then raises HapticFluidError, write_force() and close() do nothing harmful.\n"
      "hand_path: None (the hand rests at the workspace centre after homing) or waypoints\n"
      "  (t, x, y, z): times in s from the end of the homing gesture (0.6 s), increasing, and where the\n"
      "  hand pulls the grip (m, device frame, within about 0.04 m of the workspace centre), linearly\n"
      "  between them; hand_loop: start over at the first waypoint after the last (else hold it).\n"
      "  hapticfluid.hand_gestures has ready-made ones.\n"
      "hand_stiffness_homed: the hand's stiffness (N/m) once the Falcon is homed (None: hand_stiffness\n"
      "  throughout): a user who homes it, then rests the hand lightly on the grip.");
}

}  // namespace hf::python
