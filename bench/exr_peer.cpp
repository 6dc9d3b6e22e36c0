// msmcl-exr-peer: the floor of any EXR-to-EXR tool, for msmcl-e2e-bench. Reads every
// channel of a depth EXR as FLOAT (texel-interleaved, as msmcl holds depth samples), then
// writes an EXR with the channels and pixel types of an msmcl texture of the same size:
// R, G, B, A as UINT (msm64, nlq64) or one UINT R (nlq32), ZIP, on OpenEXR's thread pool
// with one thread per hardware thread, as msmcl does. The values are 16-bit codes of the
// input samples, so that the encoder gets comparable, not constant, data. No validation,
// no filtering, no atomic publication: only the decode and the encode.
//   msmcl-exr-peer IN.exr OUT.exr --channels 4|1
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfThreading.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <thread>
#include <vector>

int main(int argc, char** argv) {
    if (argc != 5 || std::strcmp(argv[3], "--channels") != 0 || (std::strcmp(argv[4], "4") != 0 && std::strcmp(argv[4], "1") != 0)) {
        std::fprintf(stderr, "usage: msmcl-exr-peer IN.exr OUT.exr --channels 4|1\n");
        return 2;
    }
    const int out_channels = std::atoi(argv[4]);
    try {
        Imf::setGlobalThreadCount(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));

        // Decode every channel into one texel-interleaved float array.
        Imf::InputFile input(argv[1], Imf::globalThreadCount());
        const Imath::Box2i window = input.header().dataWindow();
        const std::size_t width = static_cast<std::size_t>(window.max.x - window.min.x + 1);
        const std::size_t height = static_cast<std::size_t>(window.max.y - window.min.y + 1);
        std::vector<std::string> names;
        for (auto it = input.header().channels().begin(); it != input.header().channels().end(); ++it)
            names.push_back(it.name());
        const std::size_t in_channels = names.size();
        std::vector<float> samples(width * height * in_channels);
        Imf::FrameBuffer in_buffer;
        for (std::size_t c = 0; c < in_channels; ++c)
            in_buffer.insert(names[c], Imf::Slice::Make(Imf::FLOAT, samples.data() + c, window, sizeof(float) * in_channels,
                                                        sizeof(float) * in_channels * width));
        input.setFrameBuffer(in_buffer);
        input.readPixels(window.min.y, window.max.y);

        // Output planes of 16-bit codes of the samples (nlq32's one word: two codes).
        const std::size_t texels = width * height;
        std::vector<std::vector<std::uint32_t>> planes(static_cast<std::size_t>(out_channels), std::vector<std::uint32_t>(texels));
        const auto code = [&](std::size_t t, std::size_t c) {
            const float value = samples[t * in_channels + c % in_channels];
            return static_cast<std::uint32_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 65535.0f));
        };
        for (std::size_t t = 0; t < texels; ++t) {
            if (out_channels == 1) planes[0][t] = code(t, 0) | code(t, 1) << 16;
            else
                for (std::size_t c = 0; c < 4; ++c) planes[c][t] = code(t, c);
        }

        // Encode as msmcl encodes its textures: ZIP, UINT channels.
        Imf::Header header(window, window, 1.0f, Imath::V2f(0.0f, 0.0f), 1.0f, Imf::INCREASING_Y, Imf::ZIP_COMPRESSION);
        const char* out_names[4] = {"R", "G", "B", "A"};
        Imf::FrameBuffer out_buffer;
        for (int c = 0; c < out_channels; ++c) {
            header.channels().insert(out_names[c], Imf::Channel(Imf::UINT));
            out_buffer.insert(out_names[c], Imf::Slice::Make(Imf::UINT, planes[static_cast<std::size_t>(c)].data(), window,
                                                            sizeof(std::uint32_t), sizeof(std::uint32_t) * width));
        }
        Imf::OutputFile output(argv[2], header, Imf::globalThreadCount());
        output.setFrameBuffer(out_buffer);
        output.writePixels(static_cast<int>(height));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "msmcl-exr-peer: %s\n", e.what());
        return 1;
    }
    return 0;
}
