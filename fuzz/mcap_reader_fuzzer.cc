// mcap_reader_fuzzer: the MCAP bag reader (ros/src/mcap_reader.cc) on arbitrary bytes, as a
// file (an in-memory memfd, opened by its /proc path). Must never crash, hang, leak or read out
// of bounds, and must stay within its memory limits.
//
// Input: the file. Each input is read twice, with CRC checks on and off (off lets mutations
// reach the decompressors and the record parsers past the CRCs), with a 1 MiB chunk limit.
// Checks:
//   - an error names the file, has a message, and an offset within the file;
//   - an error is sticky (Next returns it again);
//   - records come in non-decreasing log time; a record's data lies within a live buffer (the
//     CDR decoder reads it; messages_fuzzer checks the decoder itself).
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "semgraph/ros/bag_reader.h"
#include "semgraph/ros/messages.h"

namespace {

[[noreturn]] void Fail(const char* what) {
  std::fprintf(stderr, "mcap_reader_fuzzer: %s\n", what);
  std::abort();
}

void CheckError(const semgraph::ros::BagError& e, const std::string& path, std::size_t size) {
  if (e.file != path) Fail("an error that does not name the file");
  if (e.message.empty()) Fail("an error without a message");
  if (e.offset > size) Fail("an error offset past the end of the file");
}

void ReadAll(const std::string& path, std::size_t size, bool verify_crc) {
  namespace r = semgraph::ros;
  r::BagReaderOptions options;
  options.max_chunk_bytes = std::uint64_t{1} << 20;
  options.verify_crc = verify_crc;
  auto opened = r::OpenMcapBag(path, options);
  if (!opened) return CheckError(opened.error(), path, size);
  r::BagRecord rec;
  std::int64_t last = 0;
  r::TFMessage tf;
  r::JointState js;
  r::String str;
  for (int n = 0;; ++n) {
    auto next = (*opened)->Next(rec);
    if (!next) {
      CheckError(next.error(), path, size);
      auto again = (*opened)->Next(rec);
      if (again.has_value() || again.error().message != next.error().message) {
        Fail("an error that is not sticky");
      }
      return;
    }
    if (!*next) return;
    if (rec.log_time_ns < last) Fail("records out of log-time order");
    last = rec.log_time_ns;
    if (rec.encoding != r::MessageEncoding::kCdr) continue;
    if (rec.kind == r::MessageKind::kTfMessage) (void)r::DecodeCdr(rec.data, tf);
    if (rec.kind == r::MessageKind::kJointState) (void)r::DecodeCdr(rec.data, js);
    if (rec.kind == r::MessageKind::kString) (void)r::DecodeCdr(rec.data, str);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const int fd = memfd_create("mcap_reader_fuzzer", MFD_CLOEXEC);
  if (fd < 0) Fail("memfd_create failed");
  for (std::size_t done = 0; done < size;) {
    const ssize_t n = write(fd, data + done, size - done);
    if (n <= 0) Fail("write to the memfd failed");
    done += static_cast<std::size_t>(n);
  }
  const std::string path = "/proc/self/fd/" + std::to_string(fd);
  ReadAll(path, size, true);
  ReadAll(path, size, false);
  close(fd);
  return 0;
}
