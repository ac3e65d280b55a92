// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/falcon/libusb_transport.h"

#include <libusb.h>

#include <algorithm>
#include <filesystem>

namespace hf::haptics::falcon {
namespace {

constexpr int kInterface = 0;
constexpr unsigned char kEndpointOut = 0x02;
constexpr unsigned char kEndpointIn = 0x81;
constexpr unsigned kControlTimeoutMs = 1000;

std::string where(int bus, int address) {
  return "Novint Falcon (USB bus " + std::to_string(bus) + " address " + std::to_string(address) + ")";
}

// libusb return code -> the matching exception, naming the stage.
[[noreturn]] void fail(const std::string& device, const std::string& stage, int code) {
  const std::string what = device + ": " + stage + " failed: " + libusb_error_name(code);
  if (code == LIBUSB_ERROR_ACCESS)
    throw UsbAccessDenied(what + ". This user may not open the Falcon.\n" + udevRuleHelp());
  if (code == LIBUSB_ERROR_NO_DEVICE)
    throw UsbUnplugged(what + ": the Falcon was unplugged or powered off; plug it in and open it again");
  if (code == LIBUSB_ERROR_BUSY)
    throw Error(what + ": the Falcon is in use by another program or another open device; close that first");
  throw Error(what);
}

// RAII libusb context.
class Context {
 public:
  Context() {
    const int rc = libusb_init(&ctx_);
    if (rc != 0) throw Error(std::string("libusb_init failed: ") + libusb_error_name(rc));
  }
  ~Context() { libusb_exit(ctx_); }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  libusb_context* get() const { return ctx_; }

 private:
  libusb_context* ctx_ = nullptr;
};

// RAII device list.
class DeviceList {
 public:
  explicit DeviceList(libusb_context* ctx) {
    const ssize_t n = libusb_get_device_list(ctx, &list_);
    if (n < 0) throw Error(std::string("libusb_get_device_list failed: ") + libusb_error_name(static_cast<int>(n)));
    count_ = static_cast<std::size_t>(n);
  }
  ~DeviceList() { libusb_free_device_list(list_, 1); }
  DeviceList(const DeviceList&) = delete;
  DeviceList& operator=(const DeviceList&) = delete;
  std::size_t size() const { return count_; }
  libusb_device* operator[](std::size_t i) const { return list_[i]; }

 private:
  libusb_device** list_ = nullptr;
  std::size_t count_ = 0;
};

bool isFalcon(libusb_device* dev) {
  libusb_device_descriptor desc{};
  if (libusb_get_device_descriptor(dev, &desc) != 0) return false;
  return desc.idVendor == kFalconVendorId && desc.idProduct == kFalconProductId;
}

}  // namespace

std::string udevRuleHelp() {
  return "Install a udev rule, then unplug and replug the Falcon:\n"
         "  echo 'SUBSYSTEM==\"usb\", ATTRS{idVendor}==\"0403\", ATTRS{idProduct}==\"cb48\", "
         "MODE=\"0660\", TAG+=\"uaccess\"' | sudo tee /etc/udev/rules.d/99-novint-falcon.rules\n"
         "  sudo udevadm control --reload-rules && sudo udevadm trigger";
}

std::vector<UsbFalconEntry> findUsbFalcons() {
  // A system with no USB bus at all (a VM, a container, a render node) has no usbfs folder, so no
  // Falcon can be attached. libusb built without udev (the wheels' static one, which finds devices
  // through sysfs and hears of new ones through netlink) fails libusb_init there; Debian's, with
  // udev, assumes /dev/bus/usb and finds nothing. Both answer "no Falcon" here.
  std::error_code ignored;
  if (!std::filesystem::exists("/dev/bus/usb", ignored) && !std::filesystem::exists("/proc/bus/usb", ignored))
    return {};
  Context ctx;
  DeviceList list(ctx.get());
  std::vector<UsbFalconEntry> found;
  for (std::size_t i = 0; i < list.size(); ++i) {
    libusb_device* dev = list[i];
    if (!isFalcon(dev)) continue;
    UsbFalconEntry entry;
    entry.bus = libusb_get_bus_number(dev);
    entry.address = libusb_get_device_address(dev);
    libusb_device_handle* handle = nullptr;
    const int rc = libusb_open(dev, &handle);
    if (rc == 0) {
      libusb_device_descriptor desc{};
      unsigned char text[128] = {};
      if (libusb_get_device_descriptor(dev, &desc) == 0 && desc.iSerialNumber != 0) {
        const int len = libusb_get_string_descriptor_ascii(handle, desc.iSerialNumber, text, sizeof text);
        if (len > 0) entry.serial.assign(reinterpret_cast<const char*>(text), static_cast<std::size_t>(len));
      }
      libusb_close(handle);
    } else {
      entry.access_denied = rc == LIBUSB_ERROR_ACCESS;
      entry.problem = std::string("libusb_open: ") + libusb_error_name(rc) +
                      (entry.access_denied ? " (no permission: see the udev rule)" : "");
    }
    found.push_back(entry);
  }
  std::sort(found.begin(), found.end(), [](const UsbFalconEntry& x, const UsbFalconEntry& y) {
    return x.bus != y.bus ? x.bus < y.bus : x.address < y.address;
  });
  return found;
}

struct LibusbTransport::Impl {
  int bus;
  int address;
  std::unique_ptr<Context> ctx;
  libusb_device_handle* handle = nullptr;
  bool claimed = false;

  std::string name() const { return where(bus, address); }

  void release() {
    if (handle != nullptr) {
      if (claimed) libusb_release_interface(handle, kInterface);
      libusb_close(handle);
    }
    handle = nullptr;
    claimed = false;
    ctx.reset();
  }
};

LibusbTransport::LibusbTransport(int bus, int address) : impl_(std::make_unique<Impl>()) {
  impl_->bus = bus;
  impl_->address = address;
}

LibusbTransport::~LibusbTransport() { close(); }

void LibusbTransport::open() {
  if (isOpen()) return;
  auto ctx = std::make_unique<Context>();
  DeviceList list(ctx->get());
  libusb_device* found = nullptr;
  for (std::size_t i = 0; i < list.size(); ++i) {
    libusb_device* dev = list[i];
    if (libusb_get_bus_number(dev) == impl_->bus && libusb_get_device_address(dev) == impl_->address && isFalcon(dev))
      found = dev;
  }
  if (found == nullptr)
    throw UsbUnplugged(impl_->name() + ": open failed: no Falcon at this bus and address any more (unplugged?); "
                       "list the Falcons again");
  libusb_device_handle* handle = nullptr;
  int rc = libusb_open(found, &handle);
  if (rc != 0) fail(impl_->name(), "libusb_open", rc);
  impl_->ctx = std::move(ctx);
  impl_->handle = handle;
  // A kernel serial driver (ftdi_sio) may hold the interface; libusb gives it back on release.
  libusb_set_auto_detach_kernel_driver(handle, 1);
  rc = libusb_claim_interface(handle, kInterface);
  if (rc != 0) {
    impl_->release();
    fail(where(impl_->bus, impl_->address), "claiming interface 0", rc);
  }
  impl_->claimed = true;
}

void LibusbTransport::close() {
  if (impl_) impl_->release();
}

bool LibusbTransport::isOpen() const { return impl_ && impl_->handle != nullptr; }

void LibusbTransport::controlOut(std::uint8_t request, std::uint16_t value, std::uint16_t index) {
  if (!isOpen()) throw Error(impl_->name() + ": control request on a closed device");
  const int rc = libusb_control_transfer(impl_->handle, LIBUSB_REQUEST_TYPE_VENDOR | LIBUSB_RECIPIENT_DEVICE |
                                                            LIBUSB_ENDPOINT_OUT,
                                         request, value, index, nullptr, 0, kControlTimeoutMs);
  if (rc < 0) fail(impl_->name(), "FTDI control request " + std::to_string(request), rc);
}

void LibusbTransport::bulkWrite(const std::uint8_t* data, std::size_t n, unsigned timeout_ms) {
  if (!isOpen()) throw Error(impl_->name() + ": write on a closed device");
  std::size_t done = 0;
  while (done < n) {
    int sent = 0;
    const int rc = libusb_bulk_transfer(impl_->handle, kEndpointOut, const_cast<std::uint8_t*>(data + done),
                                        static_cast<int>(n - done), &sent, timeout_ms);
    if (rc == LIBUSB_ERROR_TIMEOUT && sent == 0)
      throw Error(impl_->name() + ": bulk write timed out after " + std::to_string(timeout_ms) + " ms");
    if (rc != 0 && rc != LIBUSB_ERROR_TIMEOUT) fail(impl_->name(), "bulk write", rc);
    done += static_cast<std::size_t>(sent);
  }
}

std::size_t LibusbTransport::bulkRead(std::uint8_t* out, std::size_t capacity, unsigned timeout_ms) {
  if (!isOpen()) throw Error(impl_->name() + ": read on a closed device");
  int got = 0;
  const int rc = libusb_bulk_transfer(impl_->handle, kEndpointIn, out, static_cast<int>(capacity), &got, timeout_ms);
  if (rc == LIBUSB_ERROR_TIMEOUT) return static_cast<std::size_t>(got);
  if (rc != 0) fail(impl_->name(), "bulk read", rc);
  return static_cast<std::size_t>(got);
}

std::string LibusbTransport::describe() const { return where(impl_->bus, impl_->address); }

}  // namespace hf::haptics::falcon
