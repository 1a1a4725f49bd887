// Writing rendered images through OpenImageIO (see image_write.h).
#include "image_write.h"

#include <OpenImageIO/imageio.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace
{

void set_error(char *err, size_t errlen, const std::string &message)
{
    if (err && errlen > 0)
        std::snprintf(err, errlen, "%s", message.c_str());
}

bool ends_with_nocase(const std::string &s, const char *suffix)
{
    size_t n = std::strlen(suffix);
    if (s.size() < n)
        return false;
    for (size_t i = 0; i < n; ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - n + i])) != suffix[i])
            return false;
    return true;
}

} // namespace

extern "C" int halo_image_check(const char *path, char *err, size_t errlen)
{
    if (!path || !path[0]) {
        set_error(err, errlen, "empty file name");
        return -1;
    }
    std::string name(path);
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        set_error(err, errlen, name + ": cannot write: Is a directory");
        return -1;
    }
    size_t slash = name.rfind('/');
    std::string folder = slash == std::string::npos ? "." : slash == 0 ? "/" : name.substr(0, slash);
    const char *why = nullptr;
    if (stat(folder.c_str(), &st) != 0)
        why = std::strerror(errno);
    else if (!S_ISDIR(st.st_mode))
        why = std::strerror(ENOTDIR);
    else if (access(folder.c_str(), W_OK) != 0 || (access(path, F_OK) == 0 && access(path, W_OK) != 0))
        why = std::strerror(EACCES);
    if (why) {
        set_error(err, errlen, name + ": cannot write: " + why);
        return -1;
    }
    try {
        auto out = OIIO::ImageOutput::create(name);
        if (!out) {
            OIIO::geterror(); /* clear it */
            set_error(err, errlen, name + ": unknown image format (write .png or .exr)");
            return -1;
        }
    } catch (const std::exception &e) {
        set_error(err, errlen, name + ": " + e.what());
        return -1;
    }
    return 0;
}

extern "C" int halo_image_write(const char *path, int w, int h, const float *rgba, char *err, size_t errlen)
{
    if (!path || !rgba || w < 1 || h < 1) {
        set_error(err, errlen, "invalid image");
        return -1;
    }
    try {
        std::string name(path);
        bool exr = ends_with_nocase(name, ".exr");
        auto out = OIIO::ImageOutput::create(name);
        if (!out) {
            set_error(err, errlen, name + ": " + OIIO::geterror());
            return -1;
        }
        size_t count = static_cast<size_t>(w) * static_cast<size_t>(h) * 4;
        OIIO::ImageSpec spec(w, h, 4, exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
        spec.attribute("Software", "libhalo halo-render");
        if (!out->open(name, spec)) {
            set_error(err, errlen, name + ": " + out->geterror());
            return -1;
        }
        // The last row first: OpenGL's rows run bottom-up, images top-down.
        size_t row_bytes = static_cast<size_t>(w) * 4;
        bool ok;
        if (exr) {
            const float *last_row = rgba + (static_cast<size_t>(h) - 1) * row_bytes;
            ok = out->write_image(OIIO::TypeDesc::FLOAT, last_row, OIIO::AutoStride,
                                  -static_cast<OIIO::stride_t>(row_bytes * sizeof(float)));
        } else {
            std::vector<unsigned char> bytes(count);
            for (int y = 0; y < h; ++y) {
                const float *src = rgba + (static_cast<size_t>(h - 1 - y)) * row_bytes;
                unsigned char *dst = bytes.data() + static_cast<size_t>(y) * row_bytes;
                for (size_t i = 0; i < row_bytes; ++i) {
                    float v = src[i];
                    v = std::isnan(v) ? 0.0f : v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
                    dst[i] = static_cast<unsigned char>(std::lround(v * 255.0f));
                }
            }
            ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
        }
        if (!ok) {
            set_error(err, errlen, name + ": " + out->geterror());
            out->close();
            return -1;
        }
        if (!out->close()) {
            set_error(err, errlen, name + ": " + out->geterror());
            return -1;
        }
    } catch (const std::exception &e) {
        set_error(err, errlen, std::string(path) + ": " + e.what());
        return -1;
    }
    return 0;
}
