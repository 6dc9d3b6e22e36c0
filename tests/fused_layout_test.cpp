// Offline simulation of every local-memory access of the fused filter kernel
// (kernels/filter_fused_gpu.cl) for 32-wide sub-groups, with the very index and mapping
// functions the kernel uses: 32 distinct banks per access instruction (or one address for
// all lanes, a broadcast), an injective index map, race-free phases, and data-flow
// emulations that check the phases compute the 9x9 blur of the block's 32x24 interior and
// the block shift of the nlq formats (midrange of the input block's depths short of the far
// plane).
#include "kernels/fused_layout.clh"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <iterator>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace {

constexpr uint kBanks = 32;
// The kernel's second local array (the shift's step-2 results) modelled as the cells past
// the moment planes: its base address does not change which entries share a bank.
constexpr uint kShiftExtremesBase = FUSED_LOCAL_FLOATS;

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

void add_instructions(Segment& segment, const std::string& label, uint steps, const LaneAccess& access,
                      uint subgroups = FUSED_SUBGROUPS) {
    for (uint subgroup = 0; subgroup < subgroups; ++subgroup) {
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

// The kernel's accesses, phase by phase, split at its barriers; `shifted`: the nlq formats,
// whose block shift adds two segments before the resolve and 32 broadcast reads to it.
std::vector<Segment> kernel_segments(bool shifted) {
    std::vector<Segment> segments;
    Segment resolve{"resolve", {}};
    if (shifted) {
        // Shift step 1: each work-item writes the min and the max of its 5 texels.
        Segment step1{"shift step 1", {}};
        for (uint is_max = 0; is_max < 2; ++is_max)
            add_instructions(step1, is_max ? "shift partial max" : "shift partial min", 1,
                             [is_max](uint id, uint, uint& index, bool& write) {
                                 index = fused_shift_partial_index(is_max, id);
                                 write = true;
                             });
        segments.push_back(step1);
        // Shift step 2: sub-group 0 reads 16 partials per lane, writes one result per lane.
        Segment step2{"shift step 2", {}};
        add_instructions(step2, "shift step 2 read", FUSED_SHIFT_STEP2_READS,
                         [](uint id, uint k, uint& index, bool& write) {
                             index = fused_shift_step2_index(fused_lane(id), k);
                             write = false;
                         }, 1);
        add_instructions(step2, "shift step 2 write", 1,
                         [](uint id, uint, uint& index, bool& write) {
                             index = kShiftExtremesBase + fused_lane(id);
                             write = true;
                         }, 1);
        segments.push_back(step2);
        // Before the resolve: every work-item reads the 32 results, min k and max 16 + k in turn.
        add_instructions(resolve, "shift result read", FUSED_SHIFT_FLOATS,
                         [](uint, uint step, uint& index, bool& write) {
                             index = kShiftExtremesBase + (step % 2u) * (FUSED_SHIFT_FLOATS / 2) + step / 2u;
                             write = false;
                         });
    }

    // Phase 1: resolve, 5 rounds, each work-item writes 4 moments of one texel.
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
    // 20.6 KB of local memory, as the paper states; the nlq formats' shift adds 128 bytes.
    EXPECT_EQ(FUSED_LOCAL_FLOATS * sizeof(float), 20592u);
    EXPECT_EQ((FUSED_LOCAL_FLOATS + FUSED_SHIFT_FLOATS) * sizeof(float), 20720u);
    // The shift's partials (min and max of each work-item) fit the moment planes, apart.
    std::set<uint> partials;
    for (uint id = 0; id < FUSED_GROUP_SIZE; ++id)
        for (uint is_max = 0; is_max < 2; ++is_max) {
            const uint index = fused_shift_partial_index(is_max, id);
            EXPECT_LT(index, uint(FUSED_LOCAL_FLOATS)) << "id=" << id << " is_max=" << is_max;
            EXPECT_TRUE(partials.insert(index).second) << "id=" << id << " is_max=" << is_max;
        }
}

TEST(FusedLayout, EveryAccessInstructionHits32DistinctBanks) {
    for (bool shifted : {false, true}) {
        std::size_t instructions = 0;
        for (const Segment& segment : kernel_segments(shifted)) {
            for (const Instruction& instruction : segment.instructions) {
                std::set<uint> banks, addresses(instruction.index.begin(), instruction.index.end());
                for (uint index : instruction.index) banks.insert(index % kBanks);
                // A broadcast (every lane the same address, only reads) is conflict free too.
                const bool broadcast = addresses.size() == 1 && !instruction.write;
                EXPECT_TRUE(banks.size() == kBanks || broadcast)
                    << segment.name << ": " << instruction.label << " of sub-group " << instruction.subgroup;
                ++instructions;
            }
        }
        // 160 resolve + 320 horizontal + 256 vertical + 96 readout instructions; the shift:
        // 16 step-1 writes, 16 + 1 step-2 accesses of sub-group 0, 256 broadcast reads.
        EXPECT_EQ(instructions, shifted ? 1121u : 832u);
    }
}

TEST(FusedLayout, NoWorkItemTouchesACellAnotherOneWritesWithinASegment) {
    for (bool shifted : {false, true}) {
        for (const Segment& segment : kernel_segments(shifted)) {
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
}

TEST(FusedLayout, PhasesCoverEachRequiredCellExactlyOnce) {
    const std::vector<Segment> segments = kernel_segments(false);
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

TEST(FusedLayout, ShiftStepsCoverEachPartialExactlyOnce) {
    const std::vector<Segment> plain = kernel_segments(false);
    const std::vector<Segment> shifted = kernel_segments(true);
    ASSERT_EQ(shifted.size(), plain.size() + 2);
    const Segment& step1 = shifted[0];
    const Segment& step2 = shifted[1];
    std::multiset<uint> partials, results;
    for (uint id = 0; id < FUSED_GROUP_SIZE; ++id)
        for (uint is_max = 0; is_max < 2; ++is_max) partials.insert(fused_shift_partial_index(is_max, id));
    for (uint k = 0; k < FUSED_SHIFT_FLOATS; ++k) results.insert(kShiftExtremesBase + k);
    // Step 1 writes every partial once; step 2 reads each once and writes each result once.
    EXPECT_EQ(accessed(step1, true), partials);
    EXPECT_TRUE(accessed(step1, false).empty());
    EXPECT_EQ(accessed(step2, false), partials);
    EXPECT_EQ(accessed(step2, true), results);
    // The resolve segment reads every result once per work-item, and otherwise does what the
    // unshifted kernel does; the later segments are the same.
    std::multiset<uint> result_reads;
    for (uint id = 0; id < FUSED_GROUP_SIZE; ++id) result_reads.insert(results.begin(), results.end());
    EXPECT_EQ(accessed(shifted[2], false), result_reads);
    EXPECT_EQ(accessed(shifted[2], true), accessed(plain[0], true));
    for (std::size_t k = 1; k < plain.size(); ++k) {
        EXPECT_EQ(accessed(shifted[k + 2], false), accessed(plain[k], false)) << plain[k].name;
        EXPECT_EQ(accessed(shifted[k + 2], true), accessed(plain[k], true)) << plain[k].name;
    }
}

// Emulates the kernel's shift steps on the sample-0 depths of a 40x32 block (work-items in
// the given order within each segment): the shift every work-item computes.
std::vector<float> emulate_shift(const std::vector<float>& depths, bool reverse_order) {
    std::vector<float> local(FUSED_LOCAL_FLOATS + FUSED_SHIFT_FLOATS, NAN);
    auto read = [&](uint index) {
        // A cell no earlier segment wrote would be a missing barrier or a wrong index.
        EXPECT_FALSE(std::isnan(local[index])) << "cell " << index << " read before it is written";
        return local[index];
    };
    auto for_each_work_item = [&](uint count, const std::function<void(uint)>& body) {
        for (uint i = 0; i < count; ++i) body(reverse_order ? count - 1 - i : i);
    };
    // Step 1: min and max over the work-item's resolve texels short of the far plane.
    for_each_work_item(FUSED_GROUP_SIZE, [&](uint id) {
        float lowest = 1.0f, highest = -1.0f;
        for (uint round = 0; round < FUSED_RESOLVE_ROUNDS; ++round) {
            const float z = depths[fused_resolve_y(id) * FUSED_IN_W + fused_resolve_x(id, round)];
            if (z < 1.0f) {
                lowest = std::fmin(lowest, z);
                highest = std::fmax(highest, z);
            }
        }
        local[fused_shift_partial_index(0, id)] = lowest;
        local[fused_shift_partial_index(1, id)] = highest;
    });
    // Step 2: sub-group 0.
    for_each_work_item(FUSED_SUBGROUP, [&](uint id) {
        const bool is_max = id >= 16u;
        float extreme = read(fused_shift_step2_index(id, 0));
        for (uint k = 1; k < FUSED_SHIFT_STEP2_READS; ++k) {
            const float partial = read(fused_shift_step2_index(id, k));
            extreme = is_max ? std::fmax(extreme, partial) : std::fmin(extreme, partial);
        }
        local[kShiftExtremesBase + id] = extreme;
    });
    // Every work-item: the shift from the 32 results.
    std::vector<float> shifts(FUSED_GROUP_SIZE, NAN);
    for_each_work_item(FUSED_GROUP_SIZE, [&](uint id) {
        float block_min = read(kShiftExtremesBase), block_max = read(kShiftExtremesBase + FUSED_SHIFT_FLOATS / 2);
        for (uint k = 1; k < FUSED_SHIFT_FLOATS / 2; ++k) {
            block_min = std::fmin(block_min, read(kShiftExtremesBase + k));
            block_max = std::fmax(block_max, read(kShiftExtremesBase + FUSED_SHIFT_FLOATS / 2 + k));
        }
        shifts[id] = block_min <= block_max ? (block_min + block_max) * 0.5f : 1.0f;
    });
    return shifts;
}

TEST(FusedLayout, EmulatedShiftIsTheMidrangeOfTheBlockDepths) {
    const std::uint32_t seed = test_seed();
    RecordProperty("seed", std::to_string(seed));
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> value(-0.5f, 0.5f);
    std::uniform_int_distribution<uint> cell(0, FUSED_IN_W * FUSED_IN_H - 1);
    for (int trial = 0; trial < 24; ++trial) {
        std::vector<float> depths(FUSED_IN_W * FUSED_IN_H);
        for (float& z : depths) z = value(random);
        // The extremes in random cells, sometimes at the limits of the range or repeated; far
        // plane (z = 1) cells, which take no part, in some trials; one trial all far plane,
        // one all far but a single cell.
        const uint low_cell = cell(random), high_cell = cell(random);
        depths[low_cell] = trial % 3 == 0 ? -1.0f : -0.75f;
        depths[high_cell] = trial % 4 == 0 ? 0.9999999f : 0.875f;
        if (trial % 5 == 0) depths[cell(random)] = depths[low_cell];
        if (trial % 2 == 1)
            for (float& z : depths) z = cell(random) % 3 == 0 ? 1.0f : z;
        if (trial == 22) std::fill(depths.begin(), depths.end(), 1.0f);
        if (trial == 23) {
            std::fill(depths.begin(), depths.end(), 1.0f);
            depths[cell(random)] = 0.25f;
        }
        // Direct: midrange of the cells short of the far plane, 1 if none.
        std::vector<float> rendered;
        std::copy_if(depths.begin(), depths.end(), std::back_inserter(rendered), [](float z) { return z < 1.0f; });
        float expected = 1.0f;
        if (!rendered.empty())
            expected = (*std::min_element(rendered.begin(), rendered.end()) +
                        *std::max_element(rendered.begin(), rendered.end())) * 0.5f;
        for (bool reverse : {false, true})
            for (float shift : emulate_shift(depths, reverse))
                ASSERT_EQ(shift, expected) << "trial " << trial << " reverse " << reverse << ", seed " << seed;
    }
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
