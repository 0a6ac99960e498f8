// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), as MCAP stores it. Internal to ros/.
// Cost: O(n), table-driven 8 bytes at a time (slicing-by-8); no allocation.
#pragma once

#include <cstdint>
#include <span>

namespace semgraph::ros::detail {

/// Continues a CRC: Crc32Update(Crc32Update(0, a), b) == CRC of a followed by b.
[[nodiscard]] std::uint32_t Crc32Update(std::uint32_t crc,
                                        std::span<const std::uint8_t> bytes) noexcept;

}  // namespace semgraph::ros::detail
