// The OpenGL entry points grainflow uses, loaded through the current backend's
// GetProcAddress (eglGetProcAddress / OSMesaGetProcAddress). We never link libGL or
// libOpenGL: beside OSMesa that makes glGetString return NULL.
#pragma once
#include <GL/glcorearb.h>

namespace grainflow::render {

// X(return-type-pointer typedef, name without the "gl" prefix)
#define GRAINFLOW_GL_FUNCTIONS(X)                                      \
  X(PFNGLGETSTRINGPROC, GetString)                                     \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                 \
  X(PFNGLGETFLOATVPROC, GetFloatv)                                     \
  X(PFNGLGETERRORPROC, GetError)                                       \
  X(PFNGLENABLEPROC, Enable)                                           \
  X(PFNGLDISABLEPROC, Disable)                                         \
  X(PFNGLISENABLEDPROC, IsEnabled)                                     \
  X(PFNGLBLENDFUNCPROC, BlendFunc)                                     \
  X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate)                     \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                     \
  X(PFNGLDEPTHMASKPROC, DepthMask)                                     \
  X(PFNGLVIEWPORTPROC, Viewport)                                       \
  X(PFNGLSCISSORPROC, Scissor)                                         \
  X(PFNGLCLEARCOLORPROC, ClearColor)                                   \
  X(PFNGLCLEARDEPTHPROC, ClearDepth)                                   \
  X(PFNGLCLEARPROC, Clear)                                             \
  X(PFNGLFINISHPROC, Finish)                                           \
  X(PFNGLFLUSHPROC, Flush)                                             \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                 \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                   \
  X(PFNGLREADBUFFERPROC, ReadBuffer)                                   \
  X(PFNGLDRAWBUFFERPROC, DrawBuffer)                                   \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                         \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                   \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                         \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)         \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)           \
  X(PFNGLBLITFRAMEBUFFERPROC, BlitFramebuffer)                         \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                       \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                 \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                       \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                 \
  X(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, RenderbufferStorageMultisample) \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                 \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                           \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                                 \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                             \
  X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                   \
  X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D)                             \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                             \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                   \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                             \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                   \
  X(PFNGLBUFFERDATAPROC, BufferData)                                   \
  X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                             \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                         \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                   \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                         \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)         \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                 \
  X(PFNGLVERTEXATTRIBDIVISORPROC, VertexAttribDivisor)                 \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                   \
  X(PFNGLDRAWARRAYSINSTANCEDPROC, DrawArraysInstanced)                 \
  X(PFNGLCREATESHADERPROC, CreateShader)                               \
  X(PFNGLDELETESHADERPROC, DeleteShader)                               \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                               \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                             \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                 \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                       \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                             \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                             \
  X(PFNGLATTACHSHADERPROC, AttachShader)                               \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                 \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                               \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                     \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                   \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                   \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                     \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                                     \
  X(PFNGLUNIFORM2FPROC, Uniform2f)                                     \
  X(PFNGLUNIFORM3FPROC, Uniform3f)                                     \
  X(PFNGLUNIFORM4FPROC, Uniform4f)                                     \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                       \
  X(PFNGLLINEWIDTHPROC, LineWidth)

struct GlApi {
#define GRAINFLOW_GL_DECLARE(type, name) type name = nullptr;
  GRAINFLOW_GL_FUNCTIONS(GRAINFLOW_GL_DECLARE)
#undef GRAINFLOW_GL_DECLARE

  using ProcLoader = void* (*)(const char* name);
  // Fills every entry point; throws grainflow::Error naming the first one missing.
  void load(ProcLoader loader);
};

}  // namespace grainflow::render
