// One compile through glslang's C++ interface (glslang_parse.h). C++ only because
// glslang's TShader is: the rest of libhalo is C and calls halo_glslang_compile.
#include "glslang_parse.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <sys/stat.h>

namespace
{

// The folder of a file name: what comes before its last '/' ("." without one, "/" for a
// file at the root).
std::string folder_of(const std::string &file)
{
    size_t slash = file.rfind('/');
    if (slash == std::string::npos)
        return ".";
    return slash ? file.substr(0, slash) : "/";
}

// A whole regular file, or false.
bool read_file(const std::string &path, std::vector<char> &text)
{
    FILE *f = std::fopen(path.c_str(), "rb");
    if (!f)
        return false;
    struct stat st;
    bool ok = fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode);
    char chunk[8192];
    for (size_t n; ok && (n = std::fread(chunk, 1, sizeof chunk, f)) > 0;)
        text.insert(text.end(), chunk, chunk + n);
    ok = ok && !std::ferror(f);
    std::fclose(f);
    return ok;
}

// '#include "name"', looked up as glslangValidator looks it up: in the folder of the file
// that includes it, then in the folders of the files that include that one, outward to
// the shader's own folder; a '\\' in the name is a '/'. '#include <name>' finds nothing
// (glslangValidator has no system folders either).
class folder_includer : public glslang::TShader::Includer
{
  public:
    explicit folder_includer(const std::string &root) : folders_(1, root) {}

    IncludeResult *includeLocal(const char *name, const char *, size_t depth) override
    {
        // folders_[d]: the folder of the file open at include depth d (0: the shader)
        folders_.resize(depth ? depth : 1);
        for (size_t i = folders_.size(); i-- > 0;) {
            std::string path = folders_[i] + "/" + name;
            std::replace(path.begin(), path.end(), '\\', '/'); // "inc\\name.h" as glslangValidator reads it
            std::vector<char> text;
            if (!read_file(path, text))
                continue;
            std::unique_ptr<char[]> data(new char[text.size() + 1]);
            if (!text.empty())
                std::memcpy(data.get(), text.data(), text.size());
            folders_.push_back(folder_of(path));
            IncludeResult *result = new IncludeResult(path, data.get(), text.size(), data.get());
            data.release(); // releaseInclude frees it
            return result;
        }
        return nullptr;
    }

    IncludeResult *includeSystem(const char *, const char *, size_t) override { return nullptr; }

    void releaseInclude(IncludeResult *result) override
    {
        if (!result)
            return;
        delete[] static_cast<char *>(result->userData);
        delete result;
    }

  private:
    std::vector<std::string> folders_;
};

char *copy_log(const char *log)
{
    size_t n = std::strlen(log ? log : "");
    char *copy = static_cast<char *>(std::malloc(n + 1));
    if (copy)
        std::memcpy(copy, log ? log : "", n + 1);
    return copy;
}

int compile(const char *source, int vertex, const char *file, halo_glslang_link link, halo_glslang_result *out)
{
    const EShLanguage stage = vertex ? EShLangVertex : EShLangFragment;
    const int default_version = 100; // GLSL's version for a shader without #version, as glslangValidator reads it
    const EShMessages messages = EShMsgCascadingErrors;
    folder_includer includer(file ? folder_of(file) : std::string("."));
    glslang::TShader shader(stage);
    const char *name = file && *file ? file : nullptr;
    if (name)
        shader.setStringsWithLengthsAndNames(&source, nullptr, &name, 1);
    else
        shader.setStrings(&source, 1);
    shader.setEnvInput(glslang::EShSourceGlsl, stage, glslang::EShClientNone, default_version);
    shader.setEnvClient(glslang::EShClientNone, glslang::EShTargetVulkan_1_0);
    shader.setEnvTarget(glslang::EShTargetNone, glslang::EShTargetSpv_1_0);
    out->compiled =
        shader.parse(GetDefaultResources(), default_version, ENoProfile, false, false, messages, includer) ? 1 : 0;
    out->log = copy_log(shader.getInfoLog());
    if (!out->log)
        return -1;
    if (link == HALO_GLSLANG_LINK_ALWAYS || (link == HALO_GLSLANG_LINK_IF_COMPILED && out->compiled)) {
        glslang::TProgram program;
        program.addShader(&shader);
        out->linked = program.link(messages) ? 1 : 0;
        out->link_log = copy_log(program.getInfoLog());
        if (!out->link_log)
            return -1;
    }
    return 0;
}

} // namespace

extern "C" int halo_glslang_compile(const char *source, int vertex, const char *file, halo_glslang_link link,
                                    halo_glslang_result *out)
{
    *out = halo_glslang_result{1, 1, nullptr, nullptr};
    int status = -1;
    try { // no C++ exception may reach the C caller
        status = compile(source, vertex, file, link, out);
    } catch (...) {
        status = -1;
    }
    if (status)
        halo_glslang_result_free(out);
    return status;
}

extern "C" void halo_glslang_result_free(halo_glslang_result *r)
{
    std::free(r->log);
    std::free(r->link_log);
    r->log = r->link_log = nullptr;
}
