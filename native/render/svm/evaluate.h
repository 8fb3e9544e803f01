// Running a node program (program.h) at one hit: allocation-free, registers on the stack.  Out of line (evaluate.cpp):
// only materials with programs call it, from the integrator's cold per-hit material path.
#pragma once

#include <vector>

#include "program.h"
#include "render/texture.h"

namespace sphrect::render::svm {

// The program's result at hit `sg` (a float input reads its x); images: the scene's, which kImage reads.
Vec3f EvalNodeProgram(const NodeProgram& program, const std::vector<Image>& images, const ShaderGlobals& sg);

// Checks a program once (RenderScene::AddMaterial): opcodes, modes, registers, tables and images in range;
// std::invalid_argument naming what is wrong.
void CheckNodeProgram(const NodeProgram& program, size_t num_images);

}  // namespace sphrect::render::svm
