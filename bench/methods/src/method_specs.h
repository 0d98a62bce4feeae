#pragma once
// Internal: each method's spec, defined in its own file.
#include "eitbench/bench/methods/registry.h"

namespace eitbench::methods {

MethodSpec tikhonov();  // tikhonov.cpp
MethodSpec noser();     // tikhonov.cpp
MethodSpec laplace();   // tikhonov.cpp
MethodSpec smooth();    // tikhonov.cpp
MethodSpec total_variation();
MethodSpec gauss_newton();
MethodSpec greit();
MethodSpec shape();         // shape.cpp
MethodSpec shape_linear();  // shape.cpp
MethodSpec learned();

}  // namespace eitbench::methods
