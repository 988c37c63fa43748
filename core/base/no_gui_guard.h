// Force-included before every core/ source (see CMakeLists.txt): core/ is the geometry library and
// must not use OpenGL, GLFW or Dear ImGui. Their headers declare these names, so including any of
// them from core/ stops the build with "attempt to use poisoned ...".
#pragma once
#pragma GCC poison glfwInit glfwCreateWindow glfwPollEvents
#pragma GCC poison glClear glDrawArrays glDrawElements glGenBuffers glBindBuffer glViewport
#pragma GCC poison ImGui ImGuiIO
