# CMake toolchain file: Cortex-M4F (fpv4-sp-d16, hard float) with Debian's arm-none-eabi-gcc.
# SPDX-License-Identifier: MIT
#   cmake -S examples/cmake -B build/cmake-m4f -DCMAKE_TOOLCHAIN_FILE=port/cortex-m/arm-none-eabi-m4f.cmake
# Sets the compiler and the core's flags; the project chooses EDMI_REAL=float for this FPU.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
set(EDMI_CORTEX_M4F_FLAGS "-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard")
set(CMAKE_C_FLAGS_INIT "${EDMI_CORTEX_M4F_FLAGS}")
set(CMAKE_ASM_FLAGS_INIT "${EDMI_CORTEX_M4F_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${EDMI_CORTEX_M4F_FLAGS} --specs=nano.specs -nostartfiles")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
