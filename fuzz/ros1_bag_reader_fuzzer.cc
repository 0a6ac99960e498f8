// ros1_bag_reader_fuzzer: the ROS 1 bag v2.0 reader (ros/src/ros1_bag_reader.cc) on arbitrary
// bytes. Must never crash, hang or leak, and must keep bag_reader.h's promises:
//   - Open fails with an error naming the file, or returns a reader;
//   - records come in non-decreasing log time, each with a topic the reader lists, and data no
//     larger than the chunk limit;
//   - an error names the file and has a message; a finished reader repeats the same error.
// The decoded ROS 1 messages (by type name) are decoded with the codecs too, which must fail
// cleanly or succeed. The input is served as a file through a memfd (/proc/self/fd/N): the
// reader takes a path, and no disk is touched.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "semgraph/ros/bag_reader.h"
#include "semgraph/ros/messages.h"

namespace {

using namespace semgraph::ros;

[[noreturn]] void Fail(const char* why) {
  std::fprintf(stderr, "ros1_bag_reader_fuzzer: %s\n", why);
  std::abort();
}

const std::string& InputPath() {
  static const std::string path = [] {
    const int fd = memfd_create("ros1_bag_fuzz", MFD_CLOEXEC);
    if (fd < 0) Fail("memfd_create failed");
    return "/proc/self/fd/" + std::to_string(fd);
  }();
  return path;
}

void CheckError(const BagError& error) {
  if (error.file != InputPath()) Fail("an error does not name the file");
  if (error.message.empty()) Fail("an error without a message");
}

void Decode(const BagRecord& r) {
  switch (r.kind) {
    case MessageKind::kTfMessage: {
      TFMessage m;
      (void)DecodeRos1(r.data, m);
      break;
    }
    case MessageKind::kJointState: {
      JointState m;
      (void)DecodeRos1(r.data, m);
      break;
    }
    case MessageKind::kString: {
      String m;
      (void)DecodeRos1(r.data, m);
      break;
    }
    case MessageKind::kPoseWithCovarianceStamped:
    case MessageKind::kOdometry:
    case MessageKind::kOther:
      break;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = InputPath();
  const int fd = std::stoi(path.substr(path.rfind('/') + 1));
  if (ftruncate(fd, 0) != 0 ||
      (size > 0 && pwrite(fd, data, size, 0) != static_cast<ssize_t>(size))) {
    Fail("cannot write the memfd");
  }
  BagReaderOptions options;
  options.max_chunk_bytes = 1u << 20;  // keeps a bomb's cost small; the limit is what is tested
  auto reader = OpenRos1Bag(path, options);
  if (!reader) {
    CheckError(reader.error());
    return 0;
  }
  BagRecord record;
  std::int64_t last = INT64_MIN;
  for (;;) {
    auto got = (*reader)->Next(record);
    if (!got) {
      CheckError(got.error());
      auto again = (*reader)->Next(record);
      if (again || again.error().message != got.error().message) Fail("an error not repeated");
      return 0;
    }
    if (!*got) return 0;
    if (record.log_time_ns < last) Fail("records out of log-time order");
    last = record.log_time_ns;
    if (record.data.size() > options.max_chunk_bytes) Fail("a record over the chunk limit");
    bool listed = false;
    for (const BagTopic& t : (*reader)->topics()) {
      listed = listed || (t.name == record.topic && t.type_name == record.type_name);
    }
    if (!listed) Fail("a record on a topic the reader does not list");
    Decode(record);
  }
}
