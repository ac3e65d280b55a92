// SPDX-License-Identifier: GPL-3.0-or-later
// FtdiSerial over a scripted transport: the exact control requests, status bytes stripped from
// every IN packet, buffered reads, and reads that time out.
#include <gtest/gtest.h>

#include <algorithm>
#include <deque>
#include <tuple>

#include "haptics/falcon/ftdi_serial.h"

using namespace hf::haptics::falcon;

namespace {

// Records what the serial layer sends; answers bulk reads from a queue of whole transfers.
class ScriptedTransport : public UsbTransport {
 public:
  void open() override { open_ = true; }
  void close() override { open_ = false; }
  bool isOpen() const override { return open_; }
  void controlOut(std::uint8_t request, std::uint16_t value, std::uint16_t index) override {
    controls.emplace_back(request, value, index);
  }
  void bulkWrite(const std::uint8_t* data, std::size_t n, unsigned) override { written.insert(written.end(), data, data + n); }
  std::size_t bulkRead(std::uint8_t* out, std::size_t capacity, unsigned) override {
    ++reads;
    if (transfers.empty()) return 2;  // status only, as the chip sends when idle
    std::vector<std::uint8_t> t = transfers.front();
    transfers.pop_front();
    const std::size_t n = std::min(capacity, t.size());
    std::copy_n(t.begin(), n, out);
    return n;
  }
  std::string describe() const override { return "scripted"; }

  std::vector<std::tuple<int, int, int>> controls;
  std::vector<std::uint8_t> written;
  std::deque<std::vector<std::uint8_t>> transfers;
  int reads = 0;

 private:
  bool open_ = false;
};

}  // namespace

TEST(FtdiSerial, SendsTheDocumentedControlRequests) {
  ScriptedTransport usb;
  FtdiSerial serial(usb);
  serial.reset();
  serial.purge(true, true);
  serial.setLatencyTimer(16);
  serial.setBaudDivisor(0x4138);
  serial.setLine8N1();
  serial.setNoFlowControl();
  serial.setRts(false);
  serial.setDtr(false);
  serial.setDtr(true);
  const std::vector<std::tuple<int, int, int>> expected = {
      {0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {9, 16, 0}, {3, 0x4138, 0}, {4, 0x0008, 0}, {2, 0, 0},
      {1, 0x0200, 0},  // RTS low: mask 0x02 in the high byte
      {1, 0x0100, 0},  // DTR low
      {1, 0x0101, 0},  // DTR high
  };
  EXPECT_EQ(usb.controls, expected);
}

TEST(FtdiSerial, StripsStatusBytesAndBuffersTheRest) {
  ScriptedTransport usb;
  FtdiSerial serial(usb);
  usb.transfers.push_back({0x01, 0x60, 'a', 'b', 'c'});
  usb.transfers.push_back({0x01, 0x60});  // status only
  usb.transfers.push_back({0x31, 0x60, 'd', 'e'});
  std::uint8_t out[4] = {};
  ASSERT_EQ(serial.read(out, 4, std::chrono::milliseconds(100)), 4u);
  EXPECT_EQ(std::string(out, out + 4), "abcd");
  std::uint8_t rest[8] = {};
  EXPECT_EQ(serial.readBuffered(rest, sizeof rest), 1u);  // 'e' came in the last transfer
  EXPECT_EQ(rest[0], 'e');
  EXPECT_EQ(serial.readBuffered(rest, sizeof rest), 0u);
}

TEST(FtdiSerial, ReadReturnsWhatCameWhenTheTimeoutPasses) {
  ScriptedTransport usb;
  FtdiSerial serial(usb);
  usb.transfers.push_back({0x01, 0x60, 'x'});
  std::uint8_t out[16] = {};
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(serial.read(out, 16, std::chrono::milliseconds(5)), 1u);
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(5));  // waited for the rest
  EXPECT_EQ(out[0], 'x');
}

// A reader whose deadline passed before it first looked (preempted under load, or a zero
// timeout) still takes a reply that is already waiting: it is not a missed reply. Under load
// this made FalconDevice.PositionFollowsTheGripAfterHoming count one missed reply.
TEST(FtdiSerial, ReadLooksOnceEvenWhenTheDeadlineHasPassed) {
  ScriptedTransport usb;
  FtdiSerial serial(usb);
  usb.transfers.push_back({0x01, 0x60, 'r', 's'});
  std::uint8_t out[2] = {};
  EXPECT_EQ(serial.read(out, 2, std::chrono::milliseconds(0)), 2u);
  EXPECT_EQ(std::string(out, out + 2), "rs");
  EXPECT_EQ(usb.reads, 1);
}

TEST(FtdiSerial, PurgeDropsBufferedBytes) {
  ScriptedTransport usb;
  FtdiSerial serial(usb);
  usb.transfers.push_back({0x01, 0x60, 'a', 'b'});
  std::uint8_t out[1] = {};
  ASSERT_EQ(serial.read(out, 1, std::chrono::milliseconds(50)), 1u);
  serial.purge(true, false);
  EXPECT_EQ(serial.readBuffered(out, 1), 0u);
}
