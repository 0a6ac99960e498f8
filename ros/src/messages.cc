// The message codecs: one field walk per message (FieldsOf), run by a bounds-checked reader or
// a writer, in either wire format.
#include "semgraph/ros/messages.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>

namespace semgraph::ros {

std::string Describe(const CodecError& error) {
  return "byte " + std::to_string(error.offset) + ": " + error.message;
}

namespace {

enum class Wire : std::uint8_t { kCdr, kRos1 };

// The least bytes one element takes on either wire; a count larger than the bytes left divided
// by it cannot be right, and is refused before anything is allocated.
constexpr std::size_t kMinStringBytes = 4;
constexpr std::size_t kMinTransformStampedBytes = 8 + 4 + 4 + 7 * 8;
constexpr std::uint32_t kMaxLength = std::numeric_limits<std::uint32_t>::max() - 1;

class Reader {
 public:
  Reader(std::span<const std::uint8_t> bytes, Wire wire, std::size_t origin, bool swap)
      : bytes_(bytes), pos_(origin), origin_(origin), wire_(wire), swap_(swap) {}

  [[nodiscard]] bool ros1() const { return wire_ == Wire::kRos1; }
  [[nodiscard]] bool failed() const { return failed_; }
  [[nodiscard]] std::size_t pos() const { return pos_; }
  [[nodiscard]] std::size_t left() const { return bytes_.size() - pos_; }
  CodecError TakeError() { return std::move(error_); }

  void Fail(std::size_t at, std::string message) {
    if (failed_) return;
    failed_ = true;
    error_ = CodecError{at, std::move(message)};
  }

  void U32(std::uint32_t& v) { Scalar(v); }
  void I32(std::int32_t& v) { Scalar(v); }
  void F64(double& v) { Scalar(v); }

  void Stamp(Time& t) {
    if (ros1()) {
      std::uint32_t sec = 0;
      U32(sec);
      t.sec = sec;
    } else {
      std::int32_t sec = 0;
      I32(sec);
      t.sec = sec;
    }
    U32(t.nanosec);
  }

  void Str(std::string& s) {
    std::uint32_t n = 0;
    const std::size_t at = pos_;
    U32(n);
    if (failed_) return;
    if (n > left()) {
      Fail(at, "string length " + std::to_string(n) + " past the end (" + std::to_string(left()) +
                   " bytes left)");
      return;
    }
    const auto* p = reinterpret_cast<const char*>(bytes_.data() + pos_);
    if (ros1() || n == 0) {  // CDR: a length of 0 (no NUL) is read as "" like Foxglove's reader
      s.assign(p, n);
    } else {
      if (p[n - 1] != '\0') {
        Fail(at, "string of length " + std::to_string(n) + " does not end with a NUL");
        return;
      }
      const void* nul = std::memchr(p, '\0', n - 1);
      if (nul != nullptr) {
        Fail(pos_ + static_cast<std::size_t>(static_cast<const char*>(nul) - p),
             "string holds a NUL byte before its end");
        return;
      }
      s.assign(p, n - 1);
    }
    pos_ += n;
  }

  // Reads a count and checks that `count` elements of at least `min_bytes` each fit.
  std::uint32_t Count(std::size_t min_bytes) {
    std::uint32_t n = 0;
    const std::size_t at = pos_;
    U32(n);
    if (failed_) return 0;
    if (n > left() / min_bytes) {
      Fail(at, "sequence count " + std::to_string(n) + " past the end (" + std::to_string(left()) +
                   " bytes left, each element takes at least " + std::to_string(min_bytes) + ")");
      return 0;
    }
    return n;
  }

  template <class T, class F>
  void Seq(std::vector<T>& v, std::size_t min_bytes, F&& element) {
    const std::uint32_t n = Count(min_bytes);
    v.resize(n);
    for (std::uint32_t i = 0; i < n && !failed_; ++i) element(v[i]);
  }

  void Doubles(std::vector<double>& v) {
    const std::uint32_t n = Count(sizeof(double));
    v.resize(n);
    for (std::uint32_t i = 0; i < n && !failed_; ++i) F64(v[i]);
  }

  template <std::size_t N>
  void FixedDoubles(std::array<double, N>& a) {
    for (double& d : a) F64(d);
  }

 private:
  // Inlined: the decoders' inner loop (about 25 of a TFMessage's transform's 30 steps); the
  // error texts are built out of line.
  template <class T>
  [[gnu::always_inline]] inline void Scalar(T& v) {
    static_assert((sizeof(T) & (sizeof(T) - 1)) == 0);
    if (failed_) return;
    std::size_t at = pos_;
    // CDR: align to the size, counted from after the encapsulation header.
    if (!ros1()) at += (0 - (at - origin_)) & (sizeof(T) - 1);
    if (at > bytes_.size() || bytes_.size() - at < sizeof(T)) return ScalarPastTheEnd(sizeof(T));
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, bytes_.data() + at, sizeof(T));
    if (swap_ == (std::endian::native == std::endian::little)) std::reverse(raw, raw + sizeof(T));
    std::memcpy(&v, raw, sizeof(T));
    pos_ = at + sizeof(T);
  }

  [[gnu::noinline, gnu::cold]] void ScalarPastTheEnd(std::size_t size) {
    const std::size_t pad = ros1() ? 0 : (0 - (pos_ - origin_)) & (size - 1);
    if (pad > left()) {
      Fail(pos_, "message ends inside the alignment padding");
      return;
    }
    pos_ += pad;
    Fail(pos_, "message ends inside a " + std::to_string(size) + "-byte value (" +
                   std::to_string(left()) + " bytes left)");
  }

  std::span<const std::uint8_t> bytes_;
  std::size_t pos_;
  std::size_t origin_;
  Wire wire_;
  bool swap_;  // true: the data is big-endian
  bool failed_ = false;
  CodecError error_;
};

class Writer {
 public:
  Writer(std::vector<std::uint8_t>& out, Wire wire) : out_(out), wire_(wire) {
    out_.clear();
    if (wire_ == Wire::kCdr) {
      static constexpr std::uint8_t kHeader[4] = {0x00, 0x01, 0x00, 0x00};  // CDR_LE, options 0
      Append(kHeader, sizeof(kHeader));
    }
    origin_ = out_.size();
  }

  [[nodiscard]] bool ros1() const { return wire_ == Wire::kRos1; }
  [[nodiscard]] bool failed() const { return failed_; }
  CodecError TakeError() { return std::move(error_); }

  void U32(std::uint32_t v) { Scalar(v); }
  void I32(std::int32_t v) { Scalar(v); }
  void F64(double v) { Scalar(v); }

  void Stamp(const Time& t) {
    if (ros1()) {
      if (t.sec < 0 || t.sec > std::numeric_limits<std::uint32_t>::max()) {
        return Fail("Time.sec " + std::to_string(t.sec) + " outside ROS 1's uint32 range");
      }
      U32(static_cast<std::uint32_t>(t.sec));
    } else {
      if (t.sec < std::numeric_limits<std::int32_t>::min() ||
          t.sec > std::numeric_limits<std::int32_t>::max()) {
        return Fail("Time.sec " + std::to_string(t.sec) + " outside ROS 2's int32 range");
      }
      I32(static_cast<std::int32_t>(t.sec));
    }
    U32(t.nanosec);
  }

  void Str(const std::string& s) {
    if (s.size() > kMaxLength) return Fail("string longer than 2^32 - 2 bytes");
    if (ros1()) {
      U32(static_cast<std::uint32_t>(s.size()));
      Append(s.data(), s.size());
      return;
    }
    if (s.find('\0') != std::string::npos) {
      return Fail("string holds a NUL byte, which a CDR string cannot carry");
    }
    U32(static_cast<std::uint32_t>(s.size() + 1));
    Append(s.c_str(), s.size() + 1);  // with the NUL
  }

  template <class T, class F>
  void Seq(const std::vector<T>& v, std::size_t /*min_bytes*/, F&& element) {
    if (!CountOf(v.size())) return;
    for (const T& e : v) element(e);
  }

  void Doubles(const std::vector<double>& v) {
    if (!CountOf(v.size())) return;
    for (double d : v) F64(d);
  }

  template <std::size_t N>
  void FixedDoubles(const std::array<double, N>& a) {
    for (double d : a) F64(d);
  }

 private:
  void Fail(std::string message) {
    if (failed_) return;
    failed_ = true;
    error_ = CodecError{out_.size(), std::move(message)};
  }

  bool CountOf(std::size_t n) {
    if (n > kMaxLength) {
      Fail("sequence longer than 2^32 - 2 elements");
      return false;
    }
    U32(static_cast<std::uint32_t>(n));
    return true;
  }

  template <class T>
  void Scalar(T v) {
    if (!ros1())
      out_.resize(out_.size() + (sizeof(T) - (out_.size() - origin_) % sizeof(T)) % sizeof(T), 0);
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) std::reverse(raw, raw + sizeof(T));
    Append(raw, sizeof(T));
  }

  // resize + memcpy rather than insert: GCC 12 reports a false -Wstringop-overflow on insert.
  void Append(const void* p, std::size_t n) {
    if (n == 0) return;
    const std::size_t at = out_.size();
    out_.resize(at + n);
    std::memcpy(out_.data() + at, p, n);
  }

  std::vector<std::uint8_t>& out_;
  std::size_t origin_ = 0;
  Wire wire_;
  bool failed_ = false;
  CodecError error_;
};

// The fields of each message in wire order (spec: ros.md §1), for the reader (M non-const) and
// the writer (M const) alike.
template <class C, class M>
void FieldsOf(C& c, M& m) {
  using T = std::remove_const_t<M>;
  if constexpr (std::is_same_v<T, Time>) {
    c.Stamp(m);
  } else if constexpr (std::is_same_v<T, Header>) {
    if (c.ros1()) c.U32(m.seq);
    c.Stamp(m.stamp);
    c.Str(m.frame_id);
  } else if constexpr (std::is_same_v<T, Vector3> || std::is_same_v<T, Point>) {
    c.F64(m.x);
    c.F64(m.y);
    c.F64(m.z);
  } else if constexpr (std::is_same_v<T, Quaternion>) {
    c.F64(m.x);
    c.F64(m.y);
    c.F64(m.z);
    c.F64(m.w);
  } else if constexpr (std::is_same_v<T, Transform>) {
    FieldsOf(c, m.translation);
    FieldsOf(c, m.rotation);
  } else if constexpr (std::is_same_v<T, TransformStamped>) {
    FieldsOf(c, m.header);
    c.Str(m.child_frame_id);
    FieldsOf(c, m.transform);
  } else if constexpr (std::is_same_v<T, TFMessage>) {
    c.Seq(m.transforms, kMinTransformStampedBytes, [&c](auto& t) { FieldsOf(c, t); });
  } else if constexpr (std::is_same_v<T, JointState>) {
    FieldsOf(c, m.header);
    c.Seq(m.name, kMinStringBytes, [&c](auto& s) { c.Str(s); });
    c.Doubles(m.position);
    c.Doubles(m.velocity);
    c.Doubles(m.effort);
  } else if constexpr (std::is_same_v<T, Pose>) {
    FieldsOf(c, m.position);
    FieldsOf(c, m.orientation);
  } else if constexpr (std::is_same_v<T, Twist>) {
    FieldsOf(c, m.linear);
    FieldsOf(c, m.angular);
  } else if constexpr (std::is_same_v<T, PoseWithCovariance>) {
    FieldsOf(c, m.pose);
    c.FixedDoubles(m.covariance);
  } else if constexpr (std::is_same_v<T, PoseWithCovarianceStamped>) {
    FieldsOf(c, m.header);
    FieldsOf(c, m.pose);
  } else if constexpr (std::is_same_v<T, TwistWithCovariance>) {
    FieldsOf(c, m.twist);
    c.FixedDoubles(m.covariance);
  } else if constexpr (std::is_same_v<T, Odometry>) {
    FieldsOf(c, m.header);
    c.Str(m.child_frame_id);
    FieldsOf(c, m.pose);
    FieldsOf(c, m.twist);
  } else {
    static_assert(std::is_same_v<T, String>);
    c.Str(m.data);
  }
}

// The reader of a sample: checks what lies around the fields, then walks them.
template <class M>
Expected<Ok, CodecError> Decode(std::span<const std::uint8_t> bytes, M& out, Wire wire) {
  bool big_endian = false;
  std::size_t origin = 0;
  if (wire == Wire::kCdr) {
    if (bytes.size() < 4) {
      return Unexpected{CodecError{0, "CDR sample shorter than its 4-byte encapsulation header (" +
                                          std::to_string(bytes.size()) + " bytes)"}};
    }
    if (bytes[0] != 0 || bytes[1] > 1) {
      return Unexpected{CodecError{
          0, "encapsulation " + std::to_string(bytes[0]) + " " + std::to_string(bytes[1]) +
                 " is not plain CDR (00 00 big-endian or 00 01 little-endian; XCDR2 and "
                 "parameter lists are not ROS 2's encoding)"}};
    }
    big_endian = bytes[1] == 0;
    origin = 4;
  }
  Reader r(bytes, wire, origin, big_endian);
  FieldsOf(r, out);
  if (r.failed()) return Unexpected{r.TakeError()};
  // CDR writers may pad a sample to a multiple of 4 bytes (rmw_fastrtps does); nothing more.
  const std::size_t slack = wire == Wire::kCdr ? 3 : 0;
  if (r.left() > slack) {
    return Unexpected{
        CodecError{r.pos(), std::to_string(r.left()) + " bytes after the end of the message"}};
  }
  return Ok{};
}

template <class M>
Expected<Ok, CodecError> Encode(const M& msg, std::vector<std::uint8_t>& out, Wire wire) {
  Writer w(out, wire);
  FieldsOf(w, msg);
  if (w.failed()) return Unexpected{w.TakeError()};
  return Ok{};
}

}  // namespace

template <Message M>
Expected<Ok, CodecError> DecodeCdr(std::span<const std::uint8_t> bytes, M& out) {
  return Decode(bytes, out, Wire::kCdr);
}
template <Message M>
Expected<Ok, CodecError> DecodeRos1(std::span<const std::uint8_t> bytes, M& out) {
  return Decode(bytes, out, Wire::kRos1);
}
template <Message M>
Expected<Ok, CodecError> EncodeCdr(const M& msg, std::vector<std::uint8_t>& out) {
  return Encode(msg, out, Wire::kCdr);
}
template <Message M>
Expected<Ok, CodecError> EncodeRos1(const M& msg, std::vector<std::uint8_t>& out) {
  return Encode(msg, out, Wire::kRos1);
}

#define SEMGRAPH_ROS_INSTANTIATE(M)                                                               \
  template SEMGRAPH_ROS_EXPORT Expected<Ok, CodecError> DecodeCdr(std::span<const std::uint8_t>,  \
                                                                  M&);                            \
  template SEMGRAPH_ROS_EXPORT Expected<Ok, CodecError> DecodeRos1(std::span<const std::uint8_t>, \
                                                                   M&);                           \
  template SEMGRAPH_ROS_EXPORT Expected<Ok, CodecError> EncodeCdr(const M&,                       \
                                                                  std::vector<std::uint8_t>&);    \
  template SEMGRAPH_ROS_EXPORT Expected<Ok, CodecError> EncodeRos1(const M&,                      \
                                                                   std::vector<std::uint8_t>&);
SEMGRAPH_ROS_INSTANTIATE(Time)
SEMGRAPH_ROS_INSTANTIATE(Header)
SEMGRAPH_ROS_INSTANTIATE(Vector3)
SEMGRAPH_ROS_INSTANTIATE(Quaternion)
SEMGRAPH_ROS_INSTANTIATE(Transform)
SEMGRAPH_ROS_INSTANTIATE(TransformStamped)
SEMGRAPH_ROS_INSTANTIATE(TFMessage)
SEMGRAPH_ROS_INSTANTIATE(JointState)
SEMGRAPH_ROS_INSTANTIATE(String)
SEMGRAPH_ROS_INSTANTIATE(Point)
SEMGRAPH_ROS_INSTANTIATE(Pose)
SEMGRAPH_ROS_INSTANTIATE(Twist)
SEMGRAPH_ROS_INSTANTIATE(PoseWithCovariance)
SEMGRAPH_ROS_INSTANTIATE(PoseWithCovarianceStamped)
SEMGRAPH_ROS_INSTANTIATE(TwistWithCovariance)
SEMGRAPH_ROS_INSTANTIATE(Odometry)
#undef SEMGRAPH_ROS_INSTANTIATE

}  // namespace semgraph::ros
