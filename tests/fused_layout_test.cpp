// Offline simulation of every local-memory access of the fused filter kernel
// (kernels/filter_fused_gpu.cl) for 32-wide sub-groups, with the very index and mapping
// functions the kernel uses: 32 distinct banks per access instruction, an injective index
// map, race-free phases, and a data-flow emulation that checks the phases compute the
// 9x9 blur of the block's 32x24 interior.
#include "kernels/fused_layout.clh"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace {

constexpr uint kBanks = 32;

// One access instruction of one sub-group: the local index of each of its 32 lanes.
struct Instruction {
    std::string label;
    uint subgroup = 0;
    bool write = false;
    std::array<uint, FUSED_SUBGROUP> index{};
};

// The accesses between two barriers, in program order per work-item.
struct Segment {
    std::string name;
    std::vector<Instruction> instructions;
};

// Builds the instructions of a segment from a per-lane access function.
// `access(local_id, step, index, write)` fills one access for step `step` of `steps`.
using LaneAccess = std::function<void(uint local_id, uint step, uint& index, bool& write)>;

void add_instructions(Segment& segment, const std::string& label, uint steps, const LaneAccess& access) {
    for (uint subgroup = 0; subgroup < FUSED_SUBGROUPS; ++subgroup) {
        for (uint step = 0; step < steps; ++step) {
            Instruction instruction;
            instruction.label = label + " step " + std::to_string(step);
            instruction.subgroup = subgroup;
            for (uint lane = 0; lane < FUSED_SUBGROUP; ++lane) {
                bool write = false;
                access(subgroup * FUSED_SUBGROUP + lane, step, instruction.index[lane], write);
                // All lanes of one instruction do the same kind of access.
                if (lane == 0) instruction.write = write;
                EXPECT_EQ(write, instruction.write) << instruction.label;
            }
            segment.instructions.push_back(instruction);
        }
    }
}

// The kernel's accesses, phase by phase, split at its barriers.
std::vector<Segment> kernel_segments() {
    std::vector<Segment> segments;

    // Phase 1: resolve, 5 rounds, each work-item writes 4 moments of one texel.
    Segment resolve{"resolve", {}};
    for (uint j = 1; j <= 4; ++j) {
        add_instructions(resolve, "resolve write b" + std::to_string(j), FUSED_RESOLVE_ROUNDS,
                         [j](uint id, uint round, uint& index, bool& write) {
                             index = fused_local_index(j, fused_resolve_x(id, round), fused_resolve_y(id));
                             write = true;
                         });
    }
    segments.push_back(resolve);

    // Phase 2: horizontal pass, 24 reads then 16 writes per work-item.
    Segment horizontal{"horizontal", {}};
    add_instructions(horizontal, "horizontal read", FUSED_ROW_READS,
                     [](uint id, uint k, uint& index, bool& write) {
                         index = fused_local_index(fused_blur_moment(id), fused_row_read_x(id) + k, fused_row_y(id));
                         write = false;
                     });
    add_instructions(horizontal, "horizontal write", FUSED_ROW_WRITES,
                     [](uint id, uint k, uint& index, bool& write) {
                         index = fused_local_index(fused_blur_moment(id), fused_row_write_x(id) + k, fused_row_y(id));
                         write = true;
                     });
    segments.push_back(horizontal);

    // Phase 3: vertical pass, 20 reads, barrier, 12 writes in place.
    Segment vertical_read{"vertical read", {}};
    add_instructions(vertical_read, "vertical read", FUSED_COLUMN_READS,
                     [](uint id, uint k, uint& index, bool& write) {
                         index = fused_local_index(fused_blur_moment(id), fused_column_x(id), fused_column_read_y(id) + k);
                         write = false;
                     });
    segments.push_back(vertical_read);
    Segment vertical_write{"vertical write", {}};
    add_instructions(vertical_write, "vertical write", FUSED_COLUMN_WRITES,
                     [](uint id, uint k, uint& index, bool& write) {
                         index = fused_local_index(fused_blur_moment(id), fused_column_x(id), fused_column_write_y(id) + k);
                         write = true;
                     });
    segments.push_back(vertical_write);

    // Phase 4: readout, 3 rounds of 4 moment reads.
    Segment readout{"readout", {}};
    for (uint j = 1; j <= 4; ++j) {
        add_instructions(readout, "readout read b" + std::to_string(j), FUSED_READOUT_ROUNDS,
                         [j](uint id, uint round, uint& index, bool& write) {
                             index = fused_local_index(j, fused_stored_x(fused_readout_ox(id)),
                                                       fused_stored_y(fused_readout_oy(id, round)));
                             write = false;
                         });
    }
    segments.push_back(readout);
    return segments;
}

// Set of local indices of moment j over block cells (x, y) with x in xs, y in ys.
std::multiset<uint> cells(uint j, const std::vector<uint>& xs, const std::vector<uint>& ys) {
    std::multiset<uint> result;
    for (uint x : xs)
        for (uint y : ys) result.insert(fused_local_index(j, x, y));
    return result;
}

std::vector<uint> range(uint first, uint count) {
    std::vector<uint> values;
    for (uint i = 0; i < count; ++i) values.push_back(first + i);
    return values;
}

// Every index written (or read) in a segment, with multiplicity.
std::multiset<uint> accessed(const Segment& segment, bool write) {
    std::multiset<uint> result;
    for (const Instruction& instruction : segment.instructions)
        if (instruction.write == write) result.insert(instruction.index.begin(), instruction.index.end());
    return result;
}

std::uint32_t test_seed() {
    const char* text = std::getenv("MSMCL_TEST_SEED");
    return text ? static_cast<std::uint32_t>(std::strtoul(text, nullptr, 10)) : 20170726u;
}

TEST(FusedLayout, IndexMapIsInjectiveAndFitsTheLocalArray) {
    std::set<uint> seen;
    for (uint j = 1; j <= 4; ++j)
        for (uint y = 0; y < FUSED_IN_H; ++y)
            for (uint x = 0; x < FUSED_IN_W; ++x) {
                const uint index = fused_local_index(j, x, y);
                EXPECT_LT(index, uint(FUSED_LOCAL_FLOATS)) << "j=" << j << " x=" << x << " y=" << y;
                EXPECT_TRUE(seen.insert(index).second) << "j=" << j << " x=" << x << " y=" << y;
            }
    EXPECT_EQ(seen.size(), 4u * FUSED_IN_W * FUSED_IN_H);
    // 20.6 KB of local memory, as the paper states.
    EXPECT_EQ(FUSED_LOCAL_FLOATS * sizeof(float), 20592u);
}

TEST(FusedLayout, EveryAccessInstructionHits32DistinctBanks) {
    std::size_t instructions = 0;
    for (const Segment& segment : kernel_segments()) {
        for (const Instruction& instruction : segment.instructions) {
            std::set<uint> banks;
            for (uint index : instruction.index) banks.insert(index % kBanks);
            EXPECT_EQ(banks.size(), kBanks)
                << segment.name << ": " << instruction.label << " of sub-group " << instruction.subgroup;
            ++instructions;
        }
    }
    // 160 resolve + 320 horizontal + 256 vertical + 96 readout instructions.
    EXPECT_EQ(instructions, 832u);
}

TEST(FusedLayout, NoWorkItemTouchesACellAnotherOneWritesWithinASegment) {
    for (const Segment& segment : kernel_segments()) {
        // Work-items that write, and that access, each cell.
        std::map<uint, std::set<uint>> writers, users;
        for (const Instruction& instruction : segment.instructions) {
            for (uint lane = 0; lane < FUSED_SUBGROUP; ++lane) {
                const uint id = instruction.subgroup * FUSED_SUBGROUP + lane;
                users[instruction.index[lane]].insert(id);
                if (instruction.write) writers[instruction.index[lane]].insert(id);
            }
        }
        for (const auto& [index, ids] : writers) {
            EXPECT_EQ(ids.size(), 1u) << segment.name << ": cell " << index << " has several writers";
            EXPECT_EQ(users[index], ids) << segment.name << ": cell " << index << " written and used by others";
        }
    }
}

TEST(FusedLayout, PhasesCoverEachRequiredCellExactlyOnce) {
    const std::vector<Segment> segments = kernel_segments();
    const Segment& resolve = segments[0];
    const Segment& horizontal = segments[1];
    const Segment& vertical_read = segments[2];
    const Segment& vertical_write = segments[3];
    const Segment& readout = segments[4];

    std::multiset<uint> all_cells, strips, strip_outputs, readout_cells, horizontal_reads;
    const std::vector<uint> strip_columns = [] {
        std::vector<uint> columns = range(0, 16);
        for (uint x : range(24, 16)) columns.push_back(x);
        return columns;
    }();
    for (uint j = 1; j <= 4; ++j) {
        all_cells.merge(cells(j, range(0, FUSED_IN_W), range(0, FUSED_IN_H)));
        strips.merge(cells(j, strip_columns, range(0, FUSED_IN_H)));
        strip_outputs.merge(cells(j, strip_columns, range(FUSED_GUARD, FUSED_OUT_H)));
        // Left half reads columns 0..23, right half 16..39: the middle 8 twice.
        horizontal_reads.merge(cells(j, range(0, 24), range(0, FUSED_IN_H)));
        horizontal_reads.merge(cells(j, range(16, 24), range(0, FUSED_IN_H)));
        for (uint oy = 0; oy < FUSED_OUT_H; ++oy)
            for (uint ox = 0; ox < FUSED_OUT_W; ++ox)
                readout_cells.insert(fused_local_index(j, fused_stored_x(ox), fused_stored_y(oy)));
    }

    // Resolve writes the whole 40x32 block of each moment once.
    EXPECT_EQ(accessed(resolve, true), all_cells);
    // Horizontal: reads 24 values per row and half, writes every strip cell once.
    EXPECT_EQ(accessed(horizontal, false), horizontal_reads);
    EXPECT_EQ(accessed(horizontal, true), strips);
    // Vertical: reads only horizontal outputs (the upper and lower halves overlap in rows
    // 12..19), writes rows 4..27 of every strip column once.
    std::multiset<uint> vertical_reads;
    for (uint j = 1; j <= 4; ++j) {
        vertical_reads.merge(cells(j, strip_columns, range(0, 20)));
        vertical_reads.merge(cells(j, strip_columns, range(12, 20)));
    }
    EXPECT_EQ(accessed(vertical_read, false), vertical_reads);
    EXPECT_EQ(accessed(vertical_write, true), strip_outputs);
    // Readout reads exactly the vertical outputs, each once.
    EXPECT_EQ(accessed(readout, false), strip_outputs);
    EXPECT_EQ(readout_cells, strip_outputs);
    // Nothing else in those segments.
    EXPECT_TRUE(accessed(resolve, false).empty());
    EXPECT_TRUE(accessed(vertical_read, true).empty());
    EXPECT_TRUE(accessed(vertical_write, false).empty());
    EXPECT_TRUE(accessed(readout, true).empty());
}

// Runs the kernel's four phases on a float array (work-items in the given order within
// each segment) and returns the 32x24 readout of moment j = 1..4.
std::vector<float> emulate_kernel(const std::vector<float>& block, const std::array<float, 9>& taps,
                                  bool reverse_order) {
    std::vector<float> local(FUSED_LOCAL_FLOATS, NAN);
    auto for_each_work_item = [&](const std::function<void(uint)>& body) {
        for (uint i = 0; i < FUSED_GROUP_SIZE; ++i) body(reverse_order ? FUSED_GROUP_SIZE - 1 - i : i);
    };
    // Phase 1: block[(j-1)][y][x] -> local.
    for_each_work_item([&](uint id) {
        for (uint round = 0; round < FUSED_RESOLVE_ROUNDS; ++round) {
            const uint x = fused_resolve_x(id, round), y = fused_resolve_y(id);
            for (uint j = 1; j <= 4; ++j)
                local[fused_local_index(j, x, y)] = block[((j - 1) * FUSED_IN_H + y) * FUSED_IN_W + x];
        }
    });
    // Phase 2: horizontal 9 taps in registers.
    for_each_work_item([&](uint id) {
        const uint j = fused_blur_moment(id), y = fused_row_y(id);
        float row[FUSED_ROW_READS];
        for (uint k = 0; k < FUSED_ROW_READS; ++k) row[k] = local[fused_local_index(j, fused_row_read_x(id) + k, y)];
        for (uint k = 0; k < FUSED_ROW_WRITES; ++k) {
            float sum = 0.0f;
            for (uint i = 0; i < 9; ++i) sum += taps[i] * row[k + i];
            local[fused_local_index(j, fused_row_write_x(id) + k, y)] = sum;
        }
    });
    // Phase 3: vertical 9 taps, all reads before all writes.
    std::vector<std::array<float, FUSED_COLUMN_READS>> columns(FUSED_GROUP_SIZE);
    for_each_work_item([&](uint id) {
        for (uint k = 0; k < FUSED_COLUMN_READS; ++k)
            columns[id][k] = local[fused_local_index(fused_blur_moment(id), fused_column_x(id), fused_column_read_y(id) + k)];
    });
    for_each_work_item([&](uint id) {
        for (uint k = 0; k < FUSED_COLUMN_WRITES; ++k) {
            float sum = 0.0f;
            for (uint i = 0; i < 9; ++i) sum += taps[i] * columns[id][k + i];
            local[fused_local_index(fused_blur_moment(id), fused_column_x(id), fused_column_write_y(id) + k)] = sum;
        }
    });
    // Phase 4: readout.
    std::vector<float> out(4 * FUSED_OUT_W * FUSED_OUT_H, NAN);
    for_each_work_item([&](uint id) {
        for (uint round = 0; round < FUSED_READOUT_ROUNDS; ++round) {
            const uint ox = fused_readout_ox(id), oy = fused_readout_oy(id, round);
            for (uint j = 1; j <= 4; ++j)
                out[((j - 1) * FUSED_OUT_H + oy) * FUSED_OUT_W + ox] =
                    local[fused_local_index(j, fused_stored_x(ox), fused_stored_y(oy))];
        }
    });
    return out;
}

TEST(FusedLayout, EmulatedPhasesComputeThe9x9BlurOfTheBlockInterior) {
    const std::uint32_t seed = test_seed();
    std::cout << "seed " << seed << " (set MSMCL_TEST_SEED to change)\n";
    RecordProperty("seed", std::to_string(seed));
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    std::vector<float> block(4 * FUSED_IN_W * FUSED_IN_H);
    for (float& v : block) v = value(random);
    // Unsymmetric taps, so a mirrored or shifted window would show.
    std::array<float, 9> taps{};
    for (float& t : taps) t = std::uniform_real_distribution<float>(0.0f, 0.25f)(random);

    const std::vector<float> forward = emulate_kernel(block, taps, false);
    const std::vector<float> backward = emulate_kernel(block, taps, true);
    // Race-free phases: the order of work-items does not change a bit.
    EXPECT_EQ(forward, backward) << "seed " << seed;

    // Direct 2D convolution in double of the interior texel (ox+4, oy+4).
    double worst = 0.0;
    for (uint j = 0; j < 4; ++j)
        for (uint oy = 0; oy < FUSED_OUT_H; ++oy)
            for (uint ox = 0; ox < FUSED_OUT_W; ++ox) {
                double expected = 0.0;
                for (uint a = 0; a < 9; ++a)
                    for (uint b = 0; b < 9; ++b)
                        expected += double(taps[a]) * taps[b] * block[(j * FUSED_IN_H + oy + a) * FUSED_IN_W + ox + b];
                const float got = forward[(j * FUSED_OUT_H + oy) * FUSED_OUT_W + ox];
                ASSERT_FALSE(std::isnan(got)) << "j=" << j + 1 << " ox=" << ox << " oy=" << oy;
                worst = std::max(worst, std::fabs(got - expected));
            }
    // 18 float32 multiply-adds of values |v| <= 1 with taps summing to <= 2.25 per pass:
    // rounding error well below 1e-5.
    EXPECT_LT(worst, 1e-5) << "seed " << seed;
}

} // namespace
