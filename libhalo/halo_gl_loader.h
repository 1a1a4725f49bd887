/* libhalo's OpenGL loader, for a host that has none (optional: libhalo itself loads GL
 * through halo_gl_desc.get_proc_address and needs nothing of this header).
 *
 * The entry points libhalo's runtime and its example hosts call, as one table of function
 * pointers filled through the host's get-proc-address (eglGetProcAddress,
 * OSMesaGetProcAddress, glfwGetProcAddress, ...): f.CreateShader(GL_FRAGMENT_SHADER). Every
 * required one is OpenGL 3.3 core (and, but for glBindFragDataLocation and the 3D/float
 * formats' filtering, OpenGL ES 3.0); the optional ones are NULL where the context lacks
 * them. It includes Khronos' GL/glcorearb.h for the types and enums: a host with a loader
 * of its own (glad, GLEW, epoxy) includes that instead, and not this header. */
#ifndef HALO_GL_LOADER_H
#define HALO_GL_LOADER_H

#include <GL/glcorearb.h>
#include <stddef.h>

/* X(function pointer type from glcorearb.h, name without the "gl" prefix) */
#define HALO_GL_FUNCTIONS(X)                                       \
    /* state and queries */                                        \
    X(PFNGLGETERRORPROC, GetError)                                 \
    X(PFNGLGETSTRINGPROC, GetString)                               \
    X(PFNGLGETSTRINGIPROC, GetStringi)                             \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                           \
    X(PFNGLGETFLOATVPROC, GetFloatv)                               \
    X(PFNGLENABLEPROC, Enable)                                     \
    X(PFNGLDISABLEPROC, Disable)                                   \
    X(PFNGLBLENDFUNCPROC, BlendFunc)                               \
    X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate)               \
    X(PFNGLBLENDEQUATIONPROC, BlendEquation)                       \
    X(PFNGLBLENDEQUATIONSEPARATEPROC, BlendEquationSeparate)       \
    X(PFNGLDEPTHFUNCPROC, DepthFunc)                               \
    X(PFNGLDEPTHMASKPROC, DepthMask)                               \
    X(PFNGLCOLORMASKPROC, ColorMask)                               \
    X(PFNGLVIEWPORTPROC, Viewport)                                 \
    X(PFNGLSCISSORPROC, Scissor)                                   \
    X(PFNGLCLEARCOLORPROC, ClearColor)                             \
    X(PFNGLCLEARPROC, Clear)                                       \
    X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv)                       \
    X(PFNGLFINISHPROC, Finish)                                     \
    X(PFNGLFLUSHPROC, Flush)                                       \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                           \
    X(PFNGLREADPIXELSPROC, ReadPixels)                             \
    X(PFNGLREADBUFFERPROC, ReadBuffer)                             \
    X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                           \
    /* shaders and programs */                                     \
    X(PFNGLCREATESHADERPROC, CreateShader)                         \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                         \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                       \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                           \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                 \
    X(PFNGLDELETESHADERPROC, DeleteShader)                         \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                       \
    X(PFNGLATTACHSHADERPROC, AttachShader)                         \
    X(PFNGLDETACHSHADERPROC, DetachShader)                         \
    X(PFNGLBINDATTRIBLOCATIONPROC, BindAttribLocation)             \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                           \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                         \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)               \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                       \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                             \
    X(PFNGLISPROGRAMPROC, IsProgram)                               \
    X(PFNGLGETATTRIBLOCATIONPROC, GetAttribLocation)               \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)             \
    X(PFNGLGETACTIVEUNIFORMPROC, GetActiveUniform)                 \
    /* uniforms */                                                 \
    X(PFNGLUNIFORM1FPROC, Uniform1f)                               \
    X(PFNGLUNIFORM2FPROC, Uniform2f)                               \
    X(PFNGLUNIFORM3FPROC, Uniform3f)                               \
    X(PFNGLUNIFORM4FPROC, Uniform4f)                               \
    X(PFNGLUNIFORM1IPROC, Uniform1i)                               \
    X(PFNGLUNIFORM2IPROC, Uniform2i)                               \
    X(PFNGLUNIFORM3IPROC, Uniform3i)                               \
    X(PFNGLUNIFORM4IPROC, Uniform4i)                               \
    X(PFNGLUNIFORM1FVPROC, Uniform1fv)                             \
    X(PFNGLUNIFORM2FVPROC, Uniform2fv)                             \
    X(PFNGLUNIFORM3FVPROC, Uniform3fv)                             \
    X(PFNGLUNIFORM4FVPROC, Uniform4fv)                             \
    X(PFNGLUNIFORM1IVPROC, Uniform1iv)                             \
    X(PFNGLUNIFORM2IVPROC, Uniform2iv)                             \
    X(PFNGLUNIFORM3IVPROC, Uniform3iv)                             \
    X(PFNGLUNIFORM4IVPROC, Uniform4iv)                             \
    X(PFNGLUNIFORMMATRIX3FVPROC, UniformMatrix3fv)                 \
    X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                 \
    /* textures */                                                 \
    X(PFNGLGENTEXTURESPROC, GenTextures)                           \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures)                     \
    X(PFNGLBINDTEXTUREPROC, BindTexture)                           \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                       \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D)                             \
    X(PFNGLTEXIMAGE3DPROC, TexImage3D)                             \
    X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D)                       \
    X(PFNGLTEXSUBIMAGE3DPROC, TexSubImage3D)                       \
    X(PFNGLCOPYTEXSUBIMAGE3DPROC, CopyTexSubImage3D)               \
    X(PFNGLCOPYTEXSUBIMAGE2DPROC, CopyTexSubImage2D)               \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri)                       \
    X(PFNGLTEXPARAMETERFVPROC, TexParameterfv)                     \
    X(PFNGLGENERATEMIPMAPPROC, GenerateMipmap)                     \
    /* framebuffers */                                             \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                   \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)             \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                   \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)         \
    X(PFNGLFRAMEBUFFERTEXTURELAYERPROC, FramebufferTextureLayer)   \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)   \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)     \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                 \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)           \
    X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                 \
    X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)           \
    X(PFNGLBLITFRAMEBUFFERPROC, BlitFramebuffer)                   \
    /* vertex arrays, buffers, drawing */                          \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                   \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)             \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                   \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                             \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                       \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                             \
    X(PFNGLBUFFERDATAPROC, BufferData)                             \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                       \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)           \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)   \
    X(PFNGLDISABLEVERTEXATTRIBARRAYPROC, DisableVertexAttribArray) \
    X(PFNGLDRAWARRAYSPROC, DrawArrays)                             \
    X(PFNGLDRAWELEMENTSPROC, DrawElements)

/* Entry points beyond OpenGL 3.3 core and OpenGL ES 3.0, or of one of them only: loaded
 * when present, NULL otherwise (no failure); libhalo's runtime (halo_gl_create) also sets to NULL
 * those the context's version lacks (a loader may return stubs). Per-draw-buffer blending (OpenGL
 * 4.0, OpenGL ES 3.2) is what the extra outputs of image-pass programs need
 * (halo_gl_frame_attach). */
#define HALO_GL_FUNCTIONS_OPTIONAL(X)                          \
    X(PFNGLENABLEIPROC, Enablei)                               \
    X(PFNGLDISABLEIPROC, Disablei)                             \
    X(PFNGLISENABLEDIPROC, IsEnabledi)                         \
    X(PFNGLISENABLEDPROC, IsEnabled)                           \
    X(PFNGLBLENDEQUATIONIPROC, BlendEquationi)                 \
    X(PFNGLBLENDFUNCIPROC, BlendFunci)                         \
    X(PFNGLBLENDEQUATIONSEPARATEIPROC, BlendEquationSeparatei) \
    X(PFNGLBLENDFUNCSEPARATEIPROC, BlendFuncSeparatei)         \
    X(PFNGLCOLORMASKIPROC, ColorMaski)                         \
    X(PFNGLGETBOOLEANVPROC, GetBooleanv)                       \
    X(PFNGLGETTEXLEVELPARAMETERIVPROC, GetTexLevelParameteriv) \
    X(PFNGLGETINTEGERI_VPROC, GetIntegeri_v)                   \
    X(PFNGLGETBOOLEANI_VPROC, GetBooleani_v)                   \
    X(PFNGLBINDFRAGDATALOCATIONPROC, BindFragDataLocation)     \
    X(PFNGLPOLYGONMODEPROC, PolygonMode)                       \
    X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                 \
    X(PFNGLBINDBUFFERRANGEPROC, BindBufferRange)               \
    X(PFNGLGETINTEGER64I_VPROC, GetInteger64i_v)               \
    X(PFNGLGETBUFFERSUBDATAPROC, GetBufferSubData)             \
    X(PFNGLMEMORYBARRIERPROC, MemoryBarrier)

typedef struct halo_glfuncs {
#define HALO_X_GLFUNC_MEMBER(type, name) type name;
    HALO_GL_FUNCTIONS(HALO_X_GLFUNC_MEMBER)
    HALO_GL_FUNCTIONS_OPTIONAL(HALO_X_GLFUNC_MEMBER)
#undef HALO_X_GLFUNC_MEMBER
} halo_glfuncs;

#include "halo.h" /* HALO_API */

#ifdef __cplusplus
extern "C" {
#endif

/* Fills f through get_proc_address ("glCreateShader", ...); size is sizeof *f (the table
 * of the header the caller was built with: a table of another libhalo version's header,
 * whose size differs, is refused and not written). Returns 1 when every required entry
 * point was found; otherwise 0, with *missing_name (if not NULL) the first one missing
 * ("f", "size ..." or "get_proc_address" when that argument is wrong). Entry points that
 * were found are set even on failure; missing ones are NULL. */
HALO_API int halo_glfuncs_load(halo_glfuncs *f, size_t size, void *(*get_proc_address)(const char *name),
                               const char **missing_name);

#ifdef __cplusplus
}
#endif

#endif
