// The OpenGL entry points the renderer calls, loaded at run time from the context's own
// get-proc-address (OSMesaGetProcAddress or eglGetProcAddress), as glad and GLEW do.
//
// Why not link them: libOSMesa and libglvnd's libOpenGL both export glDrawElements & co, and
// the dynamic linker binds each name to one library for the whole process. Calls bound to the
// wrong one go to a dispatch table with no current context (nothing drawn, or a crash). Loaded
// per context, each Renderer calls its own backend's entry points, so an EGL and an OSMesa
// Renderer can live in one process (a test renders the same frame through both).
//
// Code that calls GL includes this header (never <GL/gl.h>) and writes the usual names:
// each is a macro for the table of the context made current on this thread
// (Renderer::render makes its own current first).
#pragma once

#include <GL/glcorearb.h>  // types, enums and PFN...PROC typedefs; no prototypes

namespace clothsim::gl {

// X(typedef suffix, name without "gl"): one line per entry point used in render/ and tests.
#define CLOTHSIM_GL_FUNCTIONS(X)                                                   \
  X(ACTIVETEXTURE, ActiveTexture)                                                  \
  X(ATTACHSHADER, AttachShader) X(BINDBUFFER, BindBuffer)                          \
  X(BINDFRAMEBUFFER, BindFramebuffer) X(BINDRENDERBUFFER, BindRenderbuffer)        \
  X(BINDTEXTURE, BindTexture)                                                      \
  X(BINDVERTEXARRAY, BindVertexArray) X(BLITFRAMEBUFFER, BlitFramebuffer)          \
  X(BUFFERDATA, BufferData) X(CHECKFRAMEBUFFERSTATUS, CheckFramebufferStatus)      \
  X(CLEAR, Clear) X(CLEARCOLOR, ClearColor) X(CLEARDEPTH, ClearDepth)              \
  X(COMPILESHADER, CompileShader) X(CREATEPROGRAM, CreateProgram)                  \
  X(CREATESHADER, CreateShader) X(DELETEFRAMEBUFFERS, DeleteFramebuffers)          \
  X(DELETEPROGRAM, DeleteProgram) X(DELETERENDERBUFFERS, DeleteRenderbuffers)      \
  X(DELETESHADER, DeleteShader) X(DEPTHFUNC, DepthFunc) X(DEPTHMASK, DepthMask)    \
  X(DISABLE, Disable) X(DRAWARRAYS, DrawArrays) X(DRAWELEMENTS, DrawElements)      \
  X(ENABLE, Enable) X(ENABLEVERTEXATTRIBARRAY, EnableVertexAttribArray)            \
  X(FINISH, Finish) X(FRAMEBUFFERRENDERBUFFER, FramebufferRenderbuffer)            \
  X(GENBUFFERS, GenBuffers) X(GENFRAMEBUFFERS, GenFramebuffers)                    \
  X(GENRENDERBUFFERS, GenRenderbuffers) X(GENVERTEXARRAYS, GenVertexArrays)        \
  X(GENTEXTURES, GenTextures)                                                      \
  X(GETERROR, GetError) X(GETFLOATV, GetFloatv) X(GETINTEGERV, GetIntegerv)        \
  X(GETPROGRAMINFOLOG, GetProgramInfoLog) X(GETPROGRAMIV, GetProgramiv)            \
  X(GETSHADERINFOLOG, GetShaderInfoLog) X(GETSHADERIV, GetShaderiv)                \
  X(GETSTRING, GetString) X(GETUNIFORMLOCATION, GetUniformLocation)                \
  X(ISPROGRAM, IsProgram) X(LINEWIDTH, LineWidth) X(LINKPROGRAM, LinkProgram)      \
  X(PIXELSTOREI, PixelStorei) X(POLYGONOFFSET, PolygonOffset)                      \
  X(READPIXELS, ReadPixels) X(RENDERBUFFERSTORAGE, RenderbufferStorage)            \
  X(RENDERBUFFERSTORAGEMULTISAMPLE, RenderbufferStorageMultisample)                \
  X(SCISSOR, Scissor) X(SHADERSOURCE, ShaderSource)                                \
  X(TEXIMAGE1D, TexImage1D) X(TEXPARAMETERI, TexParameteri)                        \
  X(UNIFORM1F, Uniform1f)                                                          \
  X(UNIFORM1I, Uniform1i) X(UNIFORM2F, Uniform2f) X(UNIFORM3F, Uniform3f)          \
  X(UNIFORM4F, Uniform4f) X(UNIFORMMATRIX4FV, UniformMatrix4fv)                    \
  X(USEPROGRAM, UseProgram) X(VERTEXATTRIBPOINTER, VertexAttribPointer)            \
  X(VIEWPORT, Viewport)

struct Functions {
#define CLOTHSIM_GL_MEMBER(upper, name) PFNGL##upper##PROC name = nullptr;
  CLOTHSIM_GL_FUNCTIONS(CLOTHSIM_GL_MEMBER)
#undef CLOTHSIM_GL_MEMBER
};

// Fills `out` through `get_proc` (name -> address). Returns the first name it could not
// find, or nullptr when all were found.
using GetProc = void* (*)(const char* name, void* user);
const char* load_functions(Functions& out, GetProc get_proc, void* user);

// The table of the context current on this thread (set by the Renderer with its context).
extern thread_local const Functions* current;

}  // namespace clothsim::gl

#define CLOTHSIM_GL_CALL(name) (::clothsim::gl::current->name)
#define glActiveTexture CLOTHSIM_GL_CALL(ActiveTexture)
#define glAttachShader CLOTHSIM_GL_CALL(AttachShader)
#define glBindBuffer CLOTHSIM_GL_CALL(BindBuffer)
#define glBindFramebuffer CLOTHSIM_GL_CALL(BindFramebuffer)
#define glBindRenderbuffer CLOTHSIM_GL_CALL(BindRenderbuffer)
#define glBindTexture CLOTHSIM_GL_CALL(BindTexture)
#define glBindVertexArray CLOTHSIM_GL_CALL(BindVertexArray)
#define glBlitFramebuffer CLOTHSIM_GL_CALL(BlitFramebuffer)
#define glBufferData CLOTHSIM_GL_CALL(BufferData)
#define glCheckFramebufferStatus CLOTHSIM_GL_CALL(CheckFramebufferStatus)
#define glClear CLOTHSIM_GL_CALL(Clear)
#define glClearColor CLOTHSIM_GL_CALL(ClearColor)
#define glClearDepth CLOTHSIM_GL_CALL(ClearDepth)
#define glCompileShader CLOTHSIM_GL_CALL(CompileShader)
#define glCreateProgram CLOTHSIM_GL_CALL(CreateProgram)
#define glCreateShader CLOTHSIM_GL_CALL(CreateShader)
#define glDeleteFramebuffers CLOTHSIM_GL_CALL(DeleteFramebuffers)
#define glDeleteProgram CLOTHSIM_GL_CALL(DeleteProgram)
#define glDeleteRenderbuffers CLOTHSIM_GL_CALL(DeleteRenderbuffers)
#define glDeleteShader CLOTHSIM_GL_CALL(DeleteShader)
#define glDepthFunc CLOTHSIM_GL_CALL(DepthFunc)
#define glDepthMask CLOTHSIM_GL_CALL(DepthMask)
#define glDisable CLOTHSIM_GL_CALL(Disable)
#define glDrawArrays CLOTHSIM_GL_CALL(DrawArrays)
#define glDrawElements CLOTHSIM_GL_CALL(DrawElements)
#define glEnable CLOTHSIM_GL_CALL(Enable)
#define glEnableVertexAttribArray CLOTHSIM_GL_CALL(EnableVertexAttribArray)
#define glFinish CLOTHSIM_GL_CALL(Finish)
#define glFramebufferRenderbuffer CLOTHSIM_GL_CALL(FramebufferRenderbuffer)
#define glGenBuffers CLOTHSIM_GL_CALL(GenBuffers)
#define glGenFramebuffers CLOTHSIM_GL_CALL(GenFramebuffers)
#define glGenRenderbuffers CLOTHSIM_GL_CALL(GenRenderbuffers)
#define glGenTextures CLOTHSIM_GL_CALL(GenTextures)
#define glGenVertexArrays CLOTHSIM_GL_CALL(GenVertexArrays)
#define glGetError CLOTHSIM_GL_CALL(GetError)
#define glGetFloatv CLOTHSIM_GL_CALL(GetFloatv)
#define glGetIntegerv CLOTHSIM_GL_CALL(GetIntegerv)
#define glGetProgramInfoLog CLOTHSIM_GL_CALL(GetProgramInfoLog)
#define glGetProgramiv CLOTHSIM_GL_CALL(GetProgramiv)
#define glGetShaderInfoLog CLOTHSIM_GL_CALL(GetShaderInfoLog)
#define glGetShaderiv CLOTHSIM_GL_CALL(GetShaderiv)
#define glGetString CLOTHSIM_GL_CALL(GetString)
#define glGetUniformLocation CLOTHSIM_GL_CALL(GetUniformLocation)
#define glIsProgram CLOTHSIM_GL_CALL(IsProgram)
#define glLineWidth CLOTHSIM_GL_CALL(LineWidth)
#define glLinkProgram CLOTHSIM_GL_CALL(LinkProgram)
#define glPixelStorei CLOTHSIM_GL_CALL(PixelStorei)
#define glPolygonOffset CLOTHSIM_GL_CALL(PolygonOffset)
#define glReadPixels CLOTHSIM_GL_CALL(ReadPixels)
#define glRenderbufferStorage CLOTHSIM_GL_CALL(RenderbufferStorage)
#define glRenderbufferStorageMultisample CLOTHSIM_GL_CALL(RenderbufferStorageMultisample)
#define glScissor CLOTHSIM_GL_CALL(Scissor)
#define glShaderSource CLOTHSIM_GL_CALL(ShaderSource)
#define glTexImage1D CLOTHSIM_GL_CALL(TexImage1D)
#define glTexParameteri CLOTHSIM_GL_CALL(TexParameteri)
#define glUniform1f CLOTHSIM_GL_CALL(Uniform1f)
#define glUniform1i CLOTHSIM_GL_CALL(Uniform1i)
#define glUniform2f CLOTHSIM_GL_CALL(Uniform2f)
#define glUniform3f CLOTHSIM_GL_CALL(Uniform3f)
#define glUniform4f CLOTHSIM_GL_CALL(Uniform4f)
#define glUniformMatrix4fv CLOTHSIM_GL_CALL(UniformMatrix4fv)
#define glUseProgram CLOTHSIM_GL_CALL(UseProgram)
#define glVertexAttribPointer CLOTHSIM_GL_CALL(VertexAttribPointer)
#define glViewport CLOTHSIM_GL_CALL(Viewport)
