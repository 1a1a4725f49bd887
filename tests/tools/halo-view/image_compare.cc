// image_compare: compares two images (PNG, EXR, anything OpenImageIO reads) of the same
// size for the halo-view tests. Prints the largest absolute difference of any channel,
// the mean absolute difference and the share of pixels with a channel differing by more
// than --threshold. Exit status: 0 within the limits (or, with --differ, different
// beyond them), 1 outside them or of different sizes, 2 usage or unreadable files.
//
//   image_compare A B [--max-abs X] [--max-share F] [--threshold T] [--differ]
//
// Defaults: --max-abs 0, --max-share 0, --threshold 0 (identical images pass).
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace
{

bool read_image(const char *path, int &width, int &height, std::vector<float> &rgba)
{
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::fprintf(stderr, "image_compare: cannot read %s: %s\n", path, OIIO::geterror().c_str());
        return false;
    }
    const OIIO::ImageSpec &spec = in->spec();
    width = spec.width;
    height = spec.height;
    int channels = spec.nchannels;
    std::vector<float> pixels(static_cast<size_t>(width) * height * channels);
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data())) {
        std::fprintf(stderr, "image_compare: cannot read %s: %s\n", path, in->geterror().c_str());
        return false;
    }
    in->close();
    rgba.assign(static_cast<size_t>(width) * height * 4, 1.0f);
    for (size_t p = 0; p < static_cast<size_t>(width) * height; ++p)
        for (int c = 0; c < 4 && c < channels; ++c)
            rgba[p * 4 + c] = pixels[p * channels + c];
    return true;
}

bool parse(const char *option, const char *text, double &out)
{
    char *end = nullptr;
    out = text ? std::strtod(text, &end) : NAN;
    if (!text || end == text || *end || !std::isfinite(out) || out < 0) {
        std::fprintf(stderr, "image_compare: %s: '%s' is not a number >= 0\n", option, text ? text : "");
        return false;
    }
    return true;
}

} // namespace

int main(int argc, char **argv)
{
    const char *paths[2] = {nullptr, nullptr};
    int path_count = 0;
    double max_abs = 0, max_share = 0, threshold = 0;
    bool differ = false;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *value = i + 1 < argc ? argv[i + 1] : nullptr;
        if (!std::strcmp(a, "--differ")) {
            differ = true;
        } else if (!std::strcmp(a, "--max-abs") || !std::strcmp(a, "--max-share") || !std::strcmp(a, "--threshold")) {
            double x;
            if (!parse(a, value, x))
                return 2;
            (a[2] == 't' ? threshold : a[6] == 'a' ? max_abs : max_share) = x;
            ++i;
        } else if (a[0] != '-' && path_count < 2) {
            paths[path_count++] = a;
        } else {
            std::fprintf(stderr, "usage: image_compare A B [--max-abs X] [--max-share F] [--threshold T] [--differ]\n");
            return 2;
        }
    }
    if (path_count != 2) {
        std::fprintf(stderr, "usage: image_compare A B [--max-abs X] [--max-share F] [--threshold T] [--differ]\n");
        return 2;
    }
    int w[2], h[2];
    std::vector<float> img[2];
    for (int k = 0; k < 2; ++k)
        if (!read_image(paths[k], w[k], h[k], img[k]))
            return 2;
    if (w[0] != w[1] || h[0] != h[1]) {
        std::printf("image_compare: %s is %dx%d, %s is %dx%d\n", paths[0], w[0], h[0], paths[1], w[1], h[1]);
        return 1;
    }
    size_t pixels = static_cast<size_t>(w[0]) * h[0], differing = 0;
    double largest = 0, sum = 0;
    for (size_t p = 0; p < pixels; ++p) {
        bool different = false;
        for (int c = 0; c < 4; ++c) {
            double d = std::fabs(static_cast<double>(img[0][p * 4 + c]) - img[1][p * 4 + c]);
            if (!(d == d))
                d = INFINITY; // NaN in one of them
            largest = d > largest ? d : largest;
            sum += d;
            different |= d > threshold;
        }
        differing += different;
    }
    double share = pixels ? static_cast<double>(differing) / pixels : 0.0;
    bool within = largest <= max_abs && share <= max_share;
    std::printf(
        "image_compare: %s vs %s (%dx%d): max abs %.9g (%.3f/255), mean abs %.3g, %zu pixels (%.4f %%) "
        "differ by more than %g\n",
        paths[0], paths[1], w[0], h[0], largest, largest * 255.0, sum / (4.0 * (pixels ? pixels : 1)), differing,
        100.0 * share, threshold);
    if (differ)
        return within ? 1 : 0;
    return within ? 0 : 1;
}
