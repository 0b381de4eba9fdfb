#pragma once
// Symbol visibility of the SDK library (hapticd::api). Plugins are built with hidden visibility, so every
// class whose type information crosses a library boundary (interfaces, exceptions) is marked here.
#define HAPTICD_API __attribute__((visibility("default")))
