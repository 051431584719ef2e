# vsmesh: mesh from depth, headless EGL context, OpenGL renderer. GL functions are loaded through
# eglGetProcAddress, so only libEGL is linked; GL/glcorearb.h (libgl-dev) gives the declarations.
find_package(OpenGL REQUIRED COMPONENTS EGL)
target_link_libraries(vsmesh PUBLIC vssynth OpenGL::EGL)
