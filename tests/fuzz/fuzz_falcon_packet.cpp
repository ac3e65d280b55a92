// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target: the Falcon's frame decoders and scanner on arbitrary bytes. Besides "no
// crash, no sanitizer report", it checks what a decoder promises: anything decoded re-encodes to
// the same values, and the scanner only ever hands out frames that decode.
#include <cstdint>
#include <cstdlib>

#include "haptics/falcon/falcon_packet.h"

using namespace hf::haptics::falcon;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (const auto report = decodeReport(data, size)) {
    const Frame again = encodeReport(*report);
    const auto back = decodeReport(again.data(), again.size());
    if (!back || back->encoder != report->encoder || back->buttons != report->buttons || back->homed != report->homed)
      std::abort();
  }
  if (const auto command = decodeCommand(data, size)) {
    const Frame again = encodeCommand(*command);
    const auto back = decodeCommand(again.data(), again.size());
    if (!back || back->motor != command->motor || back->leds != command->leds || back->homing != command->homing)
      std::abort();
  }
  // Feed the stream in uneven pieces, as USB transfers would bring it.
  FrameScanner scanner;
  std::size_t offset = 0;
  std::size_t piece = size > 0 ? (data[0] % 23) + 1 : 1;
  while (offset < size) {
    const std::size_t n = size - offset < piece ? size - offset : piece;
    scanner.push(data + offset, n);
    offset += n;
    while (const auto frame = scanner.pop())
      if (!decodeReport(frame->data(), frame->size())) std::abort();
  }
  return 0;
}
