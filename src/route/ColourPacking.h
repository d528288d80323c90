// How a routed part's colours, texel blocks and texels are laid out in bytes (private to
// route/): in the fewest bytes that give back the same bits (decision 54).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "rangefuse/core/Colour.h"

namespace rangefuse::internal {

/// Each vector below goes as one byte saying how, its length, then its elements: as they are,
/// or narrow when every element allows it. Unpacking gives back the same bits either way.
enum class Form : uint8_t { asIs = 0, narrow = 1 };

/// Whether c is colourOf of a texel, bit for bit: then `bytes` gets the texel's three channels.
bool byteColour(const Colour& c, uint8_t bytes[3]);

/// Appends the listed colours (none when v is empty): narrow, 3 bytes each, when every one is
/// a byte colour, as a colour image's are; else as floats.
void packColours(std::vector<char>& buf, const std::vector<Colour>& v,
                 const std::vector<uint32_t>& pick);
void unpackColours(const std::vector<char>& buf, size_t& pos, std::vector<Colour>& v);
void skipColours(const std::vector<char>& buf, size_t& pos);

/// Appends the listed blocks (block row and column of each point): narrow, 16 bits each, when
/// all lie in [0, 65535], as a camera's do; else 32 bits each.
void packBlocks(std::vector<char>& buf, const std::vector<std::array<int32_t, 2>>& v,
                const std::vector<uint32_t>& pick);
void unpackBlocks(const std::vector<char>& buf, size_t& pos,
                  std::vector<std::array<int32_t, 2>>& v);
void skipBlocks(const std::vector<char>& buf, size_t& pos);

/// Appends texels: narrow when each is either sampled (alpha 255) or blank (all zero), as
/// TexelImage makes them: a bit a texel saying which, then 3 bytes a sampled one. Else 4
/// bytes each.
void packTexelCells(std::vector<char>& buf, const std::vector<Texel>& v);
void unpackTexelCells(const std::vector<char>& buf, size_t& pos, std::vector<Texel>& v);
void skipTexelCells(const std::vector<char>& buf, size_t& pos);

}  // namespace rangefuse::internal
