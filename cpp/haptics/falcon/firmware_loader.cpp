// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/falcon/firmware_loader.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

namespace hf::haptics::falcon {
namespace {

constexpr std::size_t kChunkBytes = 62;

std::string hexByte(std::uint8_t v) {
  static const char* digits = "0123456789abcdef";
  return std::string("0x") + digits[v >> 4] + digits[v & 0xF];
}

}  // namespace

std::vector<std::uint8_t> readFirmwareFile(const std::string& path) {
  if (path.empty()) throw InvalidArgument("firmware path is empty: pass the path of your Falcon firmware .bin file");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw InvalidArgument("firmware file '" + path + "' cannot be found (" + std::strerror(errno) +
                          "): pass the path of the Falcon firmware .bin from Novint's SDK or driver "
                          "(e.g. nvent_firmware.bin); hapticfluid does not ship it");
  if (!S_ISREG(st.st_mode)) throw InvalidArgument("firmware path '" + path + "' is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidArgument("firmware file '" + path + "' cannot be read (" + std::strerror(errno) + ")");
  if (static_cast<std::uint64_t>(st.st_size) > kMaxFirmwareBytes)
    throw InvalidArgument("firmware file '" + path + "' has " + std::to_string(st.st_size) + " bytes, more than " +
                          std::to_string(kMaxFirmwareBytes) + ": this is not a Falcon firmware image "
                          "(those are about 7-9 KB)");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InvalidArgument("firmware file '" + path + "' could not be read to the end");
  if (bytes.empty()) throw InvalidArgument("firmware file '" + path + "' is empty: pass the Falcon firmware .bin");
  if (bytes.size() > kMaxFirmwareBytes)
    throw InvalidArgument("firmware file '" + path + "' grew past " + std::to_string(kMaxFirmwareBytes) +
                          " bytes while being read");
  return bytes;
}

void enterNormalMode(FtdiSerial& serial) {
  serial.setLatencyTimer(1);
  serial.setBaudDivisor(kBaudNormal);
  serial.purge(true, true);
}

bool FirmwareLoader::handshake() {
  for (int t = 0; t < options_.handshakeTries; ++t) {
    serial_.purge(true, false);
    serial_.write(kHello, sizeof kHello);
    std::uint8_t reply[5] = {};
    const std::size_t got = serial_.read(reply, 4, options_.handshakeTimeout);
    if (got < 4) continue;
    if (std::equal(kHelloReply, kHelloReply + 4, reply)) return true;
    // Some hosts see one extra leading 0x00.
    if (reply[0] == 0x00 && std::equal(kHelloReply, kHelloReply + 3, reply + 1) &&
        serial_.read(reply + 4, 1, options_.handshakeTimeout) == 1 && reply[4] == kHelloReply[3])
      return true;
  }
  return false;
}

std::string FirmwareLoader::attempt(const std::vector<std::uint8_t>& image) {
  serial_.purge(true, true);
  serial_.setLatencyTimer(16);
  serial_.setBaudDivisor(kBaudBootloader);
  serial_.setLine8N1();
  serial_.setNoFlowControl();
  serial_.setRts(false);
  serial_.setDtr(false);
  serial_.setDtr(true);
  if (!handshake())
    return "the bootloader did not answer the handshake in " + std::to_string(options_.handshakeTries) + " tries";
  serial_.setDtr(false);
  serial_.setBaudDivisor(kBaudUpload);
  serial_.purge(true, false);
  serial_.write(&kAutobaud, 1);
  std::uint8_t echo = 0;
  if (serial_.read(&echo, 1, options_.echoTimeout) != 1) return "timeout waiting for the bootloader's baud-lock echo";
  if (echo != kAutobaud) return "the bootloader's baud-lock echo was " + hexByte(echo) + ", not 0x41";
  std::uint8_t got[kChunkBytes];
  for (std::size_t offset = 0; offset < image.size(); offset += kChunkBytes) {
    const std::size_t n = std::min(kChunkBytes, image.size() - offset);
    serial_.write(image.data() + offset, n);
    const std::size_t echoed = serial_.read(got, n, options_.echoTimeout);
    if (echoed < n)
      return "timeout: the echo stopped at byte " + std::to_string(offset + echoed) + " of " +
             std::to_string(image.size());
    for (std::size_t i = 0; i < n; ++i)
      if (got[i] != image[offset + i])
        return "echo mismatch at byte " + std::to_string(offset + i) + " (sent " + hexByte(image[offset + i]) +
               ", echoed " + hexByte(got[i]) + ")";
  }
  enterNormalMode(serial_);
  return "";
}

void FirmwareLoader::upload(const std::vector<std::uint8_t>& image) {
  if (image.empty()) throw InvalidArgument("firmware image is empty: pass the Falcon firmware .bin");
  if (image.size() > kMaxFirmwareBytes)
    throw InvalidArgument("firmware image has " + std::to_string(image.size()) + " bytes, more than " +
                          std::to_string(kMaxFirmwareBytes) + ": this is not a Falcon firmware image");
  std::string reasons;
  attempts_ = 0;
  for (int a = 0; a < options_.uploadAttempts; ++a) {
    ++attempts_;
    const std::string why = attempt(image);
    if (why.empty()) return;
    if (reasons.find(why) == std::string::npos) reasons += (reasons.empty() ? "" : "; ") + why;
  }
  throw Error(serial_.transport().describe() + ": firmware upload failed after " + std::to_string(attempts_) +
              " attempts: " + reasons +
              ". Check the file is the Falcon's firmware (nvent_firmware.bin), then unplug the Falcon's power "
              "and USB, plug them back in and try again");
}

}  // namespace hf::haptics::falcon
