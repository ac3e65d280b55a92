// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/falcon/falcon.h"

#include "haptics/falcon/libusb_transport.h"

namespace hf::haptics::falcon {

std::string udevRule() { return udevRuleHelp(); }

std::vector<FalconListing> listFalcons(bool probeFirmware) {
  std::vector<FalconListing> out;
  const std::vector<UsbFalconEntry> found = findUsbFalcons();
  for (std::size_t i = 0; i < found.size(); ++i) {
    const UsbFalconEntry& usb = found[i];
    FalconListing item;
    item.index = static_cast<int>(i);
    item.bus = usb.bus;
    item.address = usb.address;
    item.serial = usb.serial;
    item.permissionOk = !usb.access_denied;
    item.problem = usb.problem;
    if (usb.access_denied) item.problem += "\n" + udevRuleHelp();
    if (probeFirmware && usb.problem.empty()) {
      LibusbTransport transport(usb.bus, usb.address);
      try {
        FtdiSerial serial(transport);
        item.firmwareLoaded = openAndProbeFirmware(serial, 3, std::chrono::milliseconds(20));
      } catch (const UsbAccessDenied& e) {
        item.permissionOk = false;
        item.problem = e.what();
      } catch (const Error& e) {
        item.problem = e.what();  // e.g. in use by another program (LIBUSB_ERROR_BUSY)
      }
      transport.close();
    }
    out.push_back(item);
  }
  return out;
}

std::shared_ptr<FalconDevice> openFalcon(int index, FalconOptions options) {
  const std::vector<UsbFalconEntry> found = findUsbFalcons();
  if (found.empty())
    throw UsbNotFound("no Novint Falcon (USB 0403:cb48) is plugged in: plug in its USB cable and power supply, or use "
                "open_simulated_falcon() to work without one");
  if (index < 0 || static_cast<std::size_t>(index) >= found.size())
    throw InvalidArgument("Falcon index " + std::to_string(index) + " does not exist: " +
                          std::to_string(found.size()) + " Falcon(s) plugged in, use index 0.." +
                          std::to_string(found.size() - 1));
  const UsbFalconEntry& usb = found[static_cast<std::size_t>(index)];
  if (usb.access_denied)
    throw UsbAccessDenied("Novint Falcon (USB bus " + std::to_string(usb.bus) + " address " +
                          std::to_string(usb.address) + "): this user may not open it.\n" + udevRuleHelp());
  if (options.info.name.empty()) options.info = falconInfo("Novint Falcon", "falcon", usb.serial);
  return std::make_shared<FalconDevice>(std::make_shared<LibusbTransport>(usb.bus, usb.address), std::move(options));
}

std::shared_ptr<FalconDevice> openSimulatedFalcon(const std::shared_ptr<SimulatedFalconTransport>& transport,
                                                  FalconOptions options) {
  if (!transport) throw InvalidArgument("openSimulatedFalcon needs a simulated transport, got none");
  if (options.info.name.empty()) options.info = falconInfo("Simulated Novint Falcon", "simulated_falcon", "SIM-0");
  return std::make_shared<FalconDevice>(transport, std::move(options));
}

std::function<double()> simulatedClock(const std::shared_ptr<SimulatedFalconTransport>& transport) {
  std::weak_ptr<SimulatedFalconTransport> weak = transport;
  return [weak] {
    const auto sim = weak.lock();
    return sim ? sim->time_s() : 0.0;
  };
}

}  // namespace hf::haptics::falcon
