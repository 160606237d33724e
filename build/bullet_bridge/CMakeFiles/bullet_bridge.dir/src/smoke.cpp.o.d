bullet_bridge/CMakeFiles/bullet_bridge.dir/src/smoke.cpp.o: \
 /work/main/bullet_bridge/src/smoke.cpp /usr/include/stdc-predef.h \
 /work/main/bullet_bridge/include/xpbd_bullet/smoke.hpp \
 /usr/include/bullet/btBulletDynamicsCommon.h \
 /usr/include/bullet/btBulletCollisionCommon.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btCollisionWorld.h \
 /usr/include/bullet/LinearMath/btVector3.h \
 /usr/include/bullet/LinearMath/btScalar.h /usr/include/c++/12/math.h \
 /usr/include/c++/12/cmath \
 /usr/include/x86_64-linux-gnu/c++/12/bits/c++config.h \
 /usr/include/x86_64-linux-gnu/c++/12/bits/os_defines.h \
 /usr/include/features.h /usr/include/features-time64.h \
 /usr/include/x86_64-linux-gnu/bits/wordsize.h \
 /usr/include/x86_64-linux-gnu/bits/timesize.h \
 /usr/include/x86_64-linux-gnu/sys/cdefs.h \
 /usr/include/x86_64-linux-gnu/bits/long-double.h \
 /usr/include/x86_64-linux-gnu/gnu/stubs.h \
 /usr/include/x86_64-linux-gnu/gnu/stubs-64.h \
 /usr/include/x86_64-linux-gnu/c++/12/bits/cpu_defines.h \
 /usr/include/c++/12/pstl/pstl_config.h \
 /usr/include/c++/12/bits/cpp_type_traits.h \
 /usr/include/c++/12/ext/type_traits.h /usr/include/math.h \
 /usr/include/x86_64-linux-gnu/bits/libc-header-start.h \
 /usr/include/x86_64-linux-gnu/bits/types.h \
 /usr/include/x86_64-linux-gnu/bits/typesizes.h \
 /usr/include/x86_64-linux-gnu/bits/time64.h \
 /usr/include/x86_64-linux-gnu/bits/math-vector.h \
 /usr/include/x86_64-linux-gnu/bits/libm-simd-decl-stubs.h \
 /usr/include/x86_64-linux-gnu/bits/floatn.h \
 /usr/include/x86_64-linux-gnu/bits/floatn-common.h \
 /usr/include/x86_64-linux-gnu/bits/flt-eval-method.h \
 /usr/include/x86_64-linux-gnu/bits/fp-logb.h \
 /usr/include/x86_64-linux-gnu/bits/fp-fast.h \
 /usr/include/x86_64-linux-gnu/bits/mathcalls-helper-functions.h \
 /usr/include/x86_64-linux-gnu/bits/mathcalls.h \
 /usr/include/x86_64-linux-gnu/bits/mathcalls-narrow.h \
 /usr/include/x86_64-linux-gnu/bits/iscanonical.h \
 /usr/include/c++/12/bits/std_abs.h /usr/include/stdlib.h \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/stddef.h \
 /usr/include/x86_64-linux-gnu/bits/waitflags.h \
 /usr/include/x86_64-linux-gnu/bits/waitstatus.h \
 /usr/include/x86_64-linux-gnu/bits/types/locale_t.h \
 /usr/include/x86_64-linux-gnu/bits/types/__locale_t.h \
 /usr/include/x86_64-linux-gnu/sys/types.h \
 /usr/include/x86_64-linux-gnu/bits/types/clock_t.h \
 /usr/include/x86_64-linux-gnu/bits/types/clockid_t.h \
 /usr/include/x86_64-linux-gnu/bits/types/time_t.h \
 /usr/include/x86_64-linux-gnu/bits/types/timer_t.h \
 /usr/include/x86_64-linux-gnu/bits/stdint-intn.h /usr/include/endian.h \
 /usr/include/x86_64-linux-gnu/bits/endian.h \
 /usr/include/x86_64-linux-gnu/bits/endianness.h \
 /usr/include/x86_64-linux-gnu/bits/byteswap.h \
 /usr/include/x86_64-linux-gnu/bits/uintn-identity.h \
 /usr/include/x86_64-linux-gnu/sys/select.h \
 /usr/include/x86_64-linux-gnu/bits/select.h \
 /usr/include/x86_64-linux-gnu/bits/types/sigset_t.h \
 /usr/include/x86_64-linux-gnu/bits/types/__sigset_t.h \
 /usr/include/x86_64-linux-gnu/bits/types/struct_timeval.h \
 /usr/include/x86_64-linux-gnu/bits/types/struct_timespec.h \
 /usr/include/x86_64-linux-gnu/bits/pthreadtypes.h \
 /usr/include/x86_64-linux-gnu/bits/thread-shared-types.h \
 /usr/include/x86_64-linux-gnu/bits/pthreadtypes-arch.h \
 /usr/include/x86_64-linux-gnu/bits/atomic_wide_counter.h \
 /usr/include/x86_64-linux-gnu/bits/struct_mutex.h \
 /usr/include/x86_64-linux-gnu/bits/struct_rwlock.h /usr/include/alloca.h \
 /usr/include/x86_64-linux-gnu/bits/stdlib-bsearch.h \
 /usr/include/x86_64-linux-gnu/bits/stdlib-float.h \
 /usr/include/c++/12/bits/specfun.h \
 /usr/include/c++/12/bits/stl_algobase.h \
 /usr/include/c++/12/bits/functexcept.h \
 /usr/include/c++/12/bits/exception_defines.h \
 /usr/include/c++/12/ext/numeric_traits.h \
 /usr/include/c++/12/bits/stl_pair.h /usr/include/c++/12/type_traits \
 /usr/include/c++/12/bits/move.h /usr/include/c++/12/bits/utility.h \
 /usr/include/c++/12/compare /usr/include/c++/12/concepts \
 /usr/include/c++/12/bits/stl_iterator_base_types.h \
 /usr/include/c++/12/bits/iterator_concepts.h \
 /usr/include/c++/12/bits/ptr_traits.h \
 /usr/include/c++/12/bits/ranges_cmp.h \
 /usr/include/c++/12/bits/stl_iterator_base_funcs.h \
 /usr/include/c++/12/bits/concept_check.h \
 /usr/include/c++/12/debug/assertions.h \
 /usr/include/c++/12/bits/stl_iterator.h /usr/include/c++/12/new \
 /usr/include/c++/12/bits/exception.h \
 /usr/include/c++/12/bits/stl_construct.h \
 /usr/include/c++/12/debug/debug.h \
 /usr/include/c++/12/bits/predefined_ops.h /usr/include/c++/12/limits \
 /usr/include/c++/12/tr1/gamma.tcc \
 /usr/include/c++/12/tr1/special_function_util.h \
 /usr/include/c++/12/tr1/bessel_function.tcc \
 /usr/include/c++/12/tr1/beta_function.tcc \
 /usr/include/c++/12/tr1/ell_integral.tcc \
 /usr/include/c++/12/tr1/exp_integral.tcc \
 /usr/include/c++/12/tr1/hypergeometric.tcc \
 /usr/include/c++/12/tr1/legendre_function.tcc \
 /usr/include/c++/12/tr1/modified_bessel_func.tcc \
 /usr/include/c++/12/tr1/poly_hermite.tcc \
 /usr/include/c++/12/tr1/poly_laguerre.tcc \
 /usr/include/c++/12/tr1/riemann_zeta.tcc /usr/include/c++/12/stdlib.h \
 /usr/include/c++/12/cstdlib \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/float.h /usr/include/assert.h \
 /usr/include/bullet/LinearMath/btMinMax.h \
 /usr/include/bullet/LinearMath/btAlignedAllocator.h \
 /usr/include/bullet/LinearMath/btTransform.h \
 /usr/include/bullet/LinearMath/btMatrix3x3.h \
 /usr/include/bullet/LinearMath/btVector3.h \
 /usr/include/bullet/LinearMath/btQuaternion.h \
 /usr/include/bullet/LinearMath/btQuadWord.h /usr/include/stdio.h \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/stdarg.h \
 /usr/include/x86_64-linux-gnu/bits/types/__fpos_t.h \
 /usr/include/x86_64-linux-gnu/bits/types/__mbstate_t.h \
 /usr/include/x86_64-linux-gnu/bits/types/__fpos64_t.h \
 /usr/include/x86_64-linux-gnu/bits/types/__FILE.h \
 /usr/include/x86_64-linux-gnu/bits/types/FILE.h \
 /usr/include/x86_64-linux-gnu/bits/types/struct_FILE.h \
 /usr/include/x86_64-linux-gnu/bits/types/cookie_io_functions_t.h \
 /usr/include/x86_64-linux-gnu/bits/stdio_lim.h \
 /usr/include/x86_64-linux-gnu/bits/stdio.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btCollisionObject.h \
 /usr/include/bullet/LinearMath/btMotionState.h \
 /usr/include/bullet/LinearMath/btTransform.h \
 /usr/include/bullet/LinearMath/btAlignedAllocator.h \
 /usr/include/bullet/LinearMath/btAlignedObjectArray.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btCollisionDispatcher.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btDispatcher.h \
 /usr/include/bullet/LinearMath/btScalar.h \
 /usr/include/bullet/BulletCollision/NarrowPhaseCollision/btPersistentManifold.h \
 /usr/include/bullet/BulletCollision/NarrowPhaseCollision/btManifoldPoint.h \
 /usr/include/bullet/LinearMath/btTransformUtil.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btManifoldResult.h \
 /usr/include/bullet/BulletCollision/NarrowPhaseCollision/btDiscreteCollisionDetectorInterface.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btCollisionObject.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btBroadphaseProxy.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btCollisionCreateFunc.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btOverlappingPairCache.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btBroadphaseInterface.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btBroadphaseProxy.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btOverlappingPairCallback.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btCollisionObject.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btBoxShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btPolyhedralConvexShape.h \
 /usr/include/bullet/LinearMath/btMatrix3x3.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btConvexInternalShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btConvexShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btCollisionShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btCollisionMargin.h \
 /usr/include/bullet/LinearMath/btAabbUtil2.h \
 /usr/include/bullet/LinearMath/btMinMax.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btSphereShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btCapsuleShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btCylinderShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btBoxShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btConeShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btStaticPlaneShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btConcaveShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btTriangleCallback.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btConvexHullShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btTriangleMesh.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btTriangleIndexVertexArray.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btStridingMeshInterface.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btConvexTriangleMeshShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btTriangleMeshShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btOptimizedBvh.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btQuantizedBvh.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btTriangleInfoMap.h \
 /usr/include/bullet/LinearMath/btHashMap.h /usr/include/c++/12/string \
 /usr/include/c++/12/bits/stringfwd.h \
 /usr/include/c++/12/bits/memoryfwd.h \
 /usr/include/c++/12/bits/char_traits.h \
 /usr/include/c++/12/bits/postypes.h /usr/include/c++/12/cwchar \
 /usr/include/wchar.h /usr/include/x86_64-linux-gnu/bits/wchar.h \
 /usr/include/x86_64-linux-gnu/bits/types/wint_t.h \
 /usr/include/x86_64-linux-gnu/bits/types/mbstate_t.h \
 /usr/include/c++/12/cstdint \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/stdint.h /usr/include/stdint.h \
 /usr/include/x86_64-linux-gnu/bits/stdint-uintn.h \
 /usr/include/c++/12/bits/allocator.h \
 /usr/include/x86_64-linux-gnu/c++/12/bits/c++allocator.h \
 /usr/include/c++/12/bits/new_allocator.h \
 /usr/include/c++/12/bits/localefwd.h \
 /usr/include/x86_64-linux-gnu/c++/12/bits/c++locale.h \
 /usr/include/c++/12/clocale /usr/include/locale.h \
 /usr/include/x86_64-linux-gnu/bits/locale.h /usr/include/c++/12/iosfwd \
 /usr/include/c++/12/cctype /usr/include/ctype.h \
 /usr/include/c++/12/bits/ostream_insert.h \
 /usr/include/c++/12/bits/cxxabi_forced.h \
 /usr/include/c++/12/bits/stl_function.h \
 /usr/include/c++/12/backward/binders.h \
 /usr/include/c++/12/bits/refwrap.h /usr/include/c++/12/bits/invoke.h \
 /usr/include/c++/12/bits/range_access.h \
 /usr/include/c++/12/initializer_list \
 /usr/include/c++/12/bits/basic_string.h \
 /usr/include/c++/12/ext/alloc_traits.h \
 /usr/include/c++/12/bits/alloc_traits.h /usr/include/c++/12/string_view \
 /usr/include/c++/12/bits/functional_hash.h \
 /usr/include/c++/12/bits/hash_bytes.h \
 /usr/include/c++/12/bits/ranges_base.h \
 /usr/include/c++/12/bits/max_size_type.h /usr/include/c++/12/numbers \
 /usr/include/c++/12/bits/string_view.tcc \
 /usr/include/c++/12/ext/string_conversions.h /usr/include/c++/12/cstdio \
 /usr/include/c++/12/cerrno /usr/include/errno.h \
 /usr/include/x86_64-linux-gnu/bits/errno.h /usr/include/linux/errno.h \
 /usr/include/x86_64-linux-gnu/asm/errno.h \
 /usr/include/asm-generic/errno.h /usr/include/asm-generic/errno-base.h \
 /usr/include/x86_64-linux-gnu/bits/types/error_t.h \
 /usr/include/c++/12/bits/charconv.h \
 /usr/include/c++/12/bits/basic_string.tcc \
 /usr/include/bullet/LinearMath/btAlignedObjectArray.h \
 /usr/include/bullet/LinearMath/btSerializer.h \
 /usr/include/bullet/LinearMath/btHashMap.h /usr/include/memory.h \
 /usr/include/string.h /usr/include/strings.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btScaledBvhTriangleMeshShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btTriangleMeshShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btTriangleIndexVertexArray.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btCompoundShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btTetrahedronShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btEmptyShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btMultiSphereShape.h \
 /usr/include/bullet/BulletCollision/CollisionShapes/btUniformScalingShape.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btSphereSphereCollisionAlgorithm.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btActivatingCollisionAlgorithm.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btCollisionCreateFunc.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btCollisionConfiguration.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btCollisionDispatcher.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btSimpleBroadphase.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btOverlappingPairCache.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btAxisSweep3.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btDbvtBroadphase.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btDbvt.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btAxisSweep3Internal.h \
 /usr/include/bullet/BulletCollision/BroadphaseCollision/btDbvtBroadphase.h \
 /usr/include/bullet/LinearMath/btQuaternion.h \
 /usr/include/bullet/LinearMath/btTransform.h \
 /usr/include/bullet/LinearMath/btDefaultMotionState.h \
 /usr/include/bullet/LinearMath/btMotionState.h \
 /usr/include/bullet/LinearMath/btQuickprof.h \
 /usr/include/bullet/LinearMath/btIDebugDraw.h \
 /usr/include/bullet/LinearMath/btSerializer.h \
 /usr/include/bullet/BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h \
 /usr/include/bullet/BulletDynamics/Dynamics/btDynamicsWorld.h \
 /usr/include/bullet/BulletCollision/CollisionDispatch/btCollisionWorld.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btContactSolverInfo.h \
 /usr/include/bullet/LinearMath/btThreads.h \
 /usr/include/bullet/BulletDynamics/Dynamics/btSimpleDynamicsWorld.h \
 /usr/include/bullet/BulletDynamics/Dynamics/btRigidBody.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btPoint2PointConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btJacobianEntry.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btTypedConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btSolverConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btSolverBody.h \
 /usr/include/bullet/BulletDynamics/Dynamics/btRigidBody.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btHingeConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btConeTwistConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btGeneric6DofConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btSliderConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btGeneric6DofSpringConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btGeneric6DofConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btUniversalConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btHinge2Constraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btGeneric6DofSpring2Constraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btGearConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btTypedConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btFixedConstraint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btSolverBody.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btSolverConstraint.h \
 /usr/include/bullet/BulletCollision/NarrowPhaseCollision/btManifoldPoint.h \
 /usr/include/bullet/BulletDynamics/ConstraintSolver/btConstraintSolver.h \
 /usr/include/bullet/BulletDynamics/Vehicle/btRaycastVehicle.h \
 /usr/include/bullet/BulletDynamics/Vehicle/btVehicleRaycaster.h \
 /usr/include/bullet/BulletDynamics/Vehicle/btWheelInfo.h \
 /usr/include/bullet/BulletDynamics/Dynamics/btActionInterface.h \
 /usr/include/bullet/BulletDynamics/Dynamics/btRigidBody.h \
 /usr/include/fcl/narrowphase/distance.h \
 /usr/include/fcl/narrowphase/collision_object.h \
 /usr/include/c++/12/memory /usr/include/c++/12/bits/stl_uninitialized.h \
 /usr/include/c++/12/bits/stl_tempbuf.h \
 /usr/include/c++/12/bits/stl_raw_storage_iter.h \
 /usr/include/c++/12/bits/align.h /usr/include/c++/12/bit \
 /usr/include/c++/12/bits/uses_allocator.h \
 /usr/include/c++/12/bits/unique_ptr.h /usr/include/c++/12/tuple \
 /usr/include/c++/12/ostream /usr/include/c++/12/ios \
 /usr/include/c++/12/exception /usr/include/c++/12/bits/exception_ptr.h \
 /usr/include/c++/12/bits/cxxabi_init_exception.h \
 /usr/include/c++/12/typeinfo /usr/include/c++/12/bits/nested_exception.h \
 /usr/include/c++/12/bits/ios_base.h /usr/include/c++/12/ext/atomicity.h \
 /usr/include/x86_64-linux-gnu/c++/12/bits/gthr.h \
 /usr/include/x86_64-linux-gnu/c++/12/bits/gthr-default.h \
 /usr/include/pthread.h /usr/include/sched.h \
 /usr/include/x86_64-linux-gnu/bits/sched.h \
 /usr/include/x86_64-linux-gnu/bits/types/struct_sched_param.h \
 /usr/include/x86_64-linux-gnu/bits/cpu-set.h /usr/include/time.h \
 /usr/include/x86_64-linux-gnu/bits/time.h \
 /usr/include/x86_64-linux-gnu/bits/timex.h \
 /usr/include/x86_64-linux-gnu/bits/types/struct_tm.h \
 /usr/include/x86_64-linux-gnu/bits/types/struct_itimerspec.h \
 /usr/include/x86_64-linux-gnu/bits/setjmp.h \
 /usr/include/x86_64-linux-gnu/bits/types/struct___jmp_buf_tag.h \
 /usr/include/x86_64-linux-gnu/bits/pthread_stack_min-dynamic.h \
 /usr/include/x86_64-linux-gnu/c++/12/bits/atomic_word.h \
 /usr/include/x86_64-linux-gnu/sys/single_threaded.h \
 /usr/include/c++/12/bits/locale_classes.h \
 /usr/include/c++/12/bits/locale_classes.tcc \
 /usr/include/c++/12/system_error \
 /usr/include/x86_64-linux-gnu/c++/12/bits/error_constants.h \
 /usr/include/c++/12/stdexcept /usr/include/c++/12/streambuf \
 /usr/include/c++/12/bits/streambuf.tcc \
 /usr/include/c++/12/bits/basic_ios.h \
 /usr/include/c++/12/bits/locale_facets.h /usr/include/c++/12/cwctype \
 /usr/include/wctype.h /usr/include/x86_64-linux-gnu/bits/wctype-wchar.h \
 /usr/include/x86_64-linux-gnu/c++/12/bits/ctype_base.h \
 /usr/include/c++/12/bits/streambuf_iterator.h \
 /usr/include/x86_64-linux-gnu/c++/12/bits/ctype_inline.h \
 /usr/include/c++/12/bits/locale_facets.tcc \
 /usr/include/c++/12/bits/basic_ios.tcc \
 /usr/include/c++/12/bits/ostream.tcc \
 /usr/include/c++/12/bits/shared_ptr.h \
 /usr/include/c++/12/bits/shared_ptr_base.h \
 /usr/include/c++/12/bits/allocated_ptr.h \
 /usr/include/c++/12/ext/aligned_buffer.h \
 /usr/include/c++/12/ext/concurrence.h \
 /usr/include/c++/12/bits/shared_ptr_atomic.h \
 /usr/include/c++/12/bits/atomic_base.h \
 /usr/include/c++/12/bits/atomic_lockfree_defines.h \
 /usr/include/c++/12/bits/atomic_wait.h /usr/include/c++/12/climits \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/limits.h \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/syslimits.h \
 /usr/include/limits.h /usr/include/x86_64-linux-gnu/bits/posix1_lim.h \
 /usr/include/x86_64-linux-gnu/bits/local_lim.h \
 /usr/include/linux/limits.h \
 /usr/include/x86_64-linux-gnu/bits/posix2_lim.h \
 /usr/include/x86_64-linux-gnu/bits/xopen_lim.h \
 /usr/include/x86_64-linux-gnu/bits/uio_lim.h /usr/include/unistd.h \
 /usr/include/x86_64-linux-gnu/bits/posix_opt.h \
 /usr/include/x86_64-linux-gnu/bits/environments.h \
 /usr/include/x86_64-linux-gnu/bits/confname.h \
 /usr/include/x86_64-linux-gnu/bits/getopt_posix.h \
 /usr/include/x86_64-linux-gnu/bits/getopt_core.h \
 /usr/include/x86_64-linux-gnu/bits/unistd_ext.h \
 /usr/include/linux/close_range.h /usr/include/syscall.h \
 /usr/include/x86_64-linux-gnu/sys/syscall.h \
 /usr/include/x86_64-linux-gnu/asm/unistd.h \
 /usr/include/x86_64-linux-gnu/asm/unistd_64.h \
 /usr/include/x86_64-linux-gnu/bits/syscall.h \
 /usr/include/c++/12/bits/std_mutex.h \
 /usr/include/c++/12/backward/auto_ptr.h \
 /usr/include/c++/12/bits/ranges_uninitialized.h \
 /usr/include/c++/12/bits/ranges_algobase.h \
 /usr/include/c++/12/bits/uses_allocator_args.h \
 /usr/include/c++/12/pstl/glue_memory_defs.h \
 /usr/include/c++/12/pstl/execution_defs.h \
 /usr/include/fcl/geometry/collision_geometry.h \
 /usr/include/fcl/math/bv/AABB.h /usr/include/fcl/common/types.h \
 /usr/include/c++/12/cstddef /usr/include/c++/12/vector \
 /usr/include/c++/12/bits/stl_vector.h \
 /usr/include/c++/12/bits/stl_bvector.h \
 /usr/include/c++/12/bits/vector.tcc /usr/include/c++/12/map \
 /usr/include/c++/12/bits/stl_tree.h \
 /usr/include/c++/12/bits/node_handle.h \
 /usr/include/c++/12/bits/stl_map.h \
 /usr/include/c++/12/bits/stl_multimap.h \
 /usr/include/c++/12/bits/erase_if.h /usr/include/eigen3/Eigen/Dense \
 /usr/include/eigen3/Eigen/Core \
 /usr/include/eigen3/Eigen/src/Core/util/DisableStupidWarnings.h \
 /usr/include/eigen3/Eigen/src/Core/util/Macros.h \
 /usr/include/eigen3/Eigen/src/Core/util/ConfigureVectorization.h \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/mmintrin.h \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/emmintrin.h \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/xmmintrin.h \
 /usr/lib/gcc/x86_64-linux-gnu/12/include/mm_malloc.h \
 /usr/include/c++/12/complex /usr/include/c++/12/sstream \
 /usr/include/c++/12/istream /usr/include/c++/12/bits/istream.tcc \
 /usr/include/c++/12/bits/sstream.tcc \
 /usr/include/eigen3/Eigen/src/Core/util/MKL_support.h \
 /usr/include/c++/12/cassert /usr/include/c++/12/functional \
 /usr/include/c++/12/bits/std_function.h \
 /usr/include/c++/12/unordered_map /usr/include/c++/12/bits/hashtable.h \
 /usr/include/c++/12/bits/hashtable_policy.h \
 /usr/include/c++/12/bits/enable_special_members.h \
 /usr/include/c++/12/bits/unordered_map.h /usr/include/c++/12/array \
 /usr/include/c++/12/bits/stl_algo.h \
 /usr/include/c++/12/bits/algorithmfwd.h \
 /usr/include/c++/12/bits/stl_heap.h \
 /usr/include/c++/12/bits/uniform_int_dist.h /usr/include/c++/12/cstring \
 /usr/include/c++/12/algorithm /usr/include/c++/12/bits/ranges_algo.h \
 /usr/include/c++/12/bits/ranges_util.h \
 /usr/include/c++/12/pstl/glue_algorithm_defs.h \
 /usr/include/eigen3/Eigen/src/Core/util/Constants.h \
 /usr/include/eigen3/Eigen/src/Core/util/Meta.h \
 /usr/include/eigen3/Eigen/src/Core/util/ForwardDeclarations.h \
 /usr/include/eigen3/Eigen/src/Core/util/StaticAssert.h \
 /usr/include/eigen3/Eigen/src/Core/util/XprHelper.h \
 /usr/include/eigen3/Eigen/src/Core/util/Memory.h \
 /usr/include/eigen3/Eigen/src/Core/util/IntegralConstant.h \
 /usr/include/eigen3/Eigen/src/Core/util/SymbolicIndex.h \
 /usr/include/eigen3/Eigen/src/Core/NumTraits.h \
 /usr/include/eigen3/Eigen/src/Core/MathFunctions.h \
 /usr/include/eigen3/Eigen/src/Core/GenericPacketMath.h \
 /usr/include/eigen3/Eigen/src/Core/MathFunctionsImpl.h \
 /usr/include/eigen3/Eigen/src/Core/arch/Default/ConjHelper.h \
 /usr/include/eigen3/Eigen/src/Core/arch/Default/Half.h \
 /usr/include/eigen3/Eigen/src/Core/arch/Default/BFloat16.h \
 /usr/include/eigen3/Eigen/src/Core/arch/Default/TypeCasting.h \
 /usr/include/eigen3/Eigen/src/Core/arch/Default/GenericPacketMathFunctionsFwd.h \
 /usr/include/eigen3/Eigen/src/Core/arch/SSE/PacketMath.h \
 /usr/include/eigen3/Eigen/src/Core/arch/SSE/TypeCasting.h \
 /usr/include/eigen3/Eigen/src/Core/arch/SSE/MathFunctions.h \
 /usr/include/eigen3/Eigen/src/Core/arch/SSE/Complex.h \
 /usr/include/eigen3/Eigen/src/Core/arch/Default/Settings.h \
 /usr/include/eigen3/Eigen/src/Core/arch/Default/GenericPacketMathFunctions.h \
 /usr/include/eigen3/Eigen/src/Core/functors/TernaryFunctors.h \
 /usr/include/eigen3/Eigen/src/Core/functors/BinaryFunctors.h \
 /usr/include/eigen3/Eigen/src/Core/functors/UnaryFunctors.h \
 /usr/include/eigen3/Eigen/src/Core/functors/NullaryFunctors.h \
 /usr/include/eigen3/Eigen/src/Core/functors/StlFunctors.h \
 /usr/include/eigen3/Eigen/src/Core/functors/AssignmentFunctors.h \
 /usr/include/eigen3/Eigen/src/Core/util/IndexedViewHelper.h \
 /usr/include/eigen3/Eigen/src/Core/util/ReshapedHelper.h \
 /usr/include/eigen3/Eigen/src/Core/ArithmeticSequence.h \
 /usr/include/eigen3/Eigen/src/Core/IO.h \
 /usr/include/eigen3/Eigen/src/Core/DenseCoeffsBase.h \
 /usr/include/eigen3/Eigen/src/Core/DenseBase.h \
 /usr/include/eigen3/Eigen/src/plugins/CommonCwiseUnaryOps.h \
 /usr/include/eigen3/Eigen/src/plugins/BlockMethods.h \
 /usr/include/eigen3/Eigen/src/plugins/IndexedViewMethods.h \
 /usr/include/eigen3/Eigen/src/plugins/IndexedViewMethods.h \
 /usr/include/eigen3/Eigen/src/plugins/ReshapedMethods.h \
 /usr/include/eigen3/Eigen/src/plugins/ReshapedMethods.h \
 /usr/include/eigen3/Eigen/src/Core/MatrixBase.h \
 /usr/include/eigen3/Eigen/src/plugins/CommonCwiseBinaryOps.h \
 /usr/include/eigen3/Eigen/src/plugins/MatrixCwiseUnaryOps.h \
 /usr/include/eigen3/Eigen/src/plugins/MatrixCwiseBinaryOps.h \
 /usr/include/eigen3/Eigen/src/Core/EigenBase.h \
 /usr/include/eigen3/Eigen/src/Core/Product.h \
 /usr/include/eigen3/Eigen/src/Core/CoreEvaluators.h \
 /usr/include/eigen3/Eigen/src/Core/AssignEvaluator.h \
 /usr/include/eigen3/Eigen/src/Core/Assign.h \
 /usr/include/eigen3/Eigen/src/Core/ArrayBase.h \
 /usr/include/eigen3/Eigen/src/plugins/ArrayCwiseUnaryOps.h \
 /usr/include/eigen3/Eigen/src/plugins/ArrayCwiseBinaryOps.h \
 /usr/include/eigen3/Eigen/src/Core/util/BlasUtil.h \
 /usr/include/eigen3/Eigen/src/Core/DenseStorage.h \
 /usr/include/eigen3/Eigen/src/Core/NestByValue.h \
 /usr/include/eigen3/Eigen/src/Core/ReturnByValue.h \
 /usr/include/eigen3/Eigen/src/Core/NoAlias.h \
 /usr/include/eigen3/Eigen/src/Core/PlainObjectBase.h \
 /usr/include/eigen3/Eigen/src/Core/Matrix.h \
 /usr/include/eigen3/Eigen/src/Core/Array.h \
 /usr/include/eigen3/Eigen/src/Core/CwiseTernaryOp.h \
 /usr/include/eigen3/Eigen/src/Core/CwiseBinaryOp.h \
 /usr/include/eigen3/Eigen/src/Core/CwiseUnaryOp.h \
 /usr/include/eigen3/Eigen/src/Core/CwiseNullaryOp.h \
 /usr/include/eigen3/Eigen/src/Core/CwiseUnaryView.h \
 /usr/include/eigen3/Eigen/src/Core/SelfCwiseBinaryOp.h \
 /usr/include/eigen3/Eigen/src/Core/Dot.h \
 /usr/include/eigen3/Eigen/src/Core/StableNorm.h \
 /usr/include/eigen3/Eigen/src/Core/Stride.h \
 /usr/include/eigen3/Eigen/src/Core/MapBase.h \
 /usr/include/eigen3/Eigen/src/Core/Map.h \
 /usr/include/eigen3/Eigen/src/Core/Ref.h \
 /usr/include/eigen3/Eigen/src/Core/Block.h \
 /usr/include/eigen3/Eigen/src/Core/VectorBlock.h \
 /usr/include/eigen3/Eigen/src/Core/IndexedView.h \
 /usr/include/eigen3/Eigen/src/Core/Reshaped.h \
 /usr/include/eigen3/Eigen/src/Core/Transpose.h \
 /usr/include/eigen3/Eigen/src/Core/DiagonalMatrix.h \
 /usr/include/eigen3/Eigen/src/Core/Diagonal.h \
 /usr/include/eigen3/Eigen/src/Core/DiagonalProduct.h \
 /usr/include/eigen3/Eigen/src/Core/Redux.h \
 /usr/include/eigen3/Eigen/src/Core/Visitor.h \
 /usr/include/eigen3/Eigen/src/Core/Fuzzy.h \
 /usr/include/eigen3/Eigen/src/Core/Swap.h \
 /usr/include/eigen3/Eigen/src/Core/CommaInitializer.h \
 /usr/include/eigen3/Eigen/src/Core/GeneralProduct.h \
 /usr/include/eigen3/Eigen/src/Core/Solve.h \
 /usr/include/eigen3/Eigen/src/Core/Inverse.h \
 /usr/include/eigen3/Eigen/src/Core/SolverBase.h \
 /usr/include/eigen3/Eigen/src/Core/PermutationMatrix.h \
 /usr/include/eigen3/Eigen/src/Core/Transpositions.h \
 /usr/include/eigen3/Eigen/src/Core/TriangularMatrix.h \
 /usr/include/eigen3/Eigen/src/Core/SelfAdjointView.h \
 /usr/include/eigen3/Eigen/src/Core/products/GeneralBlockPanelKernel.h \
 /usr/include/eigen3/Eigen/src/Core/products/Parallelizer.h \
 /usr/include/c++/12/atomic \
 /usr/include/eigen3/Eigen/src/Core/ProductEvaluators.h \
 /usr/include/eigen3/Eigen/src/Core/products/GeneralMatrixVector.h \
 /usr/include/eigen3/Eigen/src/Core/products/GeneralMatrixMatrix.h \
 /usr/include/eigen3/Eigen/src/Core/SolveTriangular.h \
 /usr/include/eigen3/Eigen/src/Core/products/GeneralMatrixMatrixTriangular.h \
 /usr/include/eigen3/Eigen/src/Core/products/SelfadjointMatrixVector.h \
 /usr/include/eigen3/Eigen/src/Core/products/SelfadjointMatrixMatrix.h \
 /usr/include/eigen3/Eigen/src/Core/products/SelfadjointProduct.h \
 /usr/include/eigen3/Eigen/src/Core/products/SelfadjointRank2Update.h \
 /usr/include/eigen3/Eigen/src/Core/products/TriangularMatrixVector.h \
 /usr/include/eigen3/Eigen/src/Core/products/TriangularMatrixMatrix.h \
 /usr/include/eigen3/Eigen/src/Core/products/TriangularSolverMatrix.h \
 /usr/include/eigen3/Eigen/src/Core/products/TriangularSolverVector.h \
 /usr/include/eigen3/Eigen/src/Core/BandMatrix.h \
 /usr/include/eigen3/Eigen/src/Core/CoreIterators.h \
 /usr/include/eigen3/Eigen/src/Core/ConditionEstimator.h \
 /usr/include/eigen3/Eigen/src/Core/BooleanRedux.h \
 /usr/include/eigen3/Eigen/src/Core/Select.h \
 /usr/include/eigen3/Eigen/src/Core/VectorwiseOp.h \
 /usr/include/eigen3/Eigen/src/Core/PartialReduxEvaluator.h \
 /usr/include/eigen3/Eigen/src/Core/Random.h \
 /usr/include/eigen3/Eigen/src/Core/Replicate.h \
 /usr/include/eigen3/Eigen/src/Core/Reverse.h \
 /usr/include/eigen3/Eigen/src/Core/ArrayWrapper.h \
 /usr/include/eigen3/Eigen/src/Core/StlIterators.h \
 /usr/include/eigen3/Eigen/src/Core/GlobalFunctions.h \
 /usr/include/eigen3/Eigen/src/Core/util/ReenableStupidWarnings.h \
 /usr/include/eigen3/Eigen/LU /usr/include/eigen3/Eigen/src/misc/Kernel.h \
 /usr/include/eigen3/Eigen/src/misc/Image.h \
 /usr/include/eigen3/Eigen/src/LU/FullPivLU.h \
 /usr/include/eigen3/Eigen/src/LU/PartialPivLU.h \
 /usr/include/eigen3/Eigen/src/LU/Determinant.h \
 /usr/include/eigen3/Eigen/src/LU/InverseImpl.h \
 /usr/include/eigen3/Eigen/src/LU/arch/InverseSize4.h \
 /usr/include/eigen3/Eigen/Cholesky /usr/include/eigen3/Eigen/Jacobi \
 /usr/include/eigen3/Eigen/src/Jacobi/Jacobi.h \
 /usr/include/eigen3/Eigen/src/Cholesky/LLT.h \
 /usr/include/eigen3/Eigen/src/Cholesky/LDLT.h \
 /usr/include/eigen3/Eigen/QR /usr/include/eigen3/Eigen/Householder \
 /usr/include/eigen3/Eigen/src/Householder/Householder.h \
 /usr/include/eigen3/Eigen/src/Householder/HouseholderSequence.h \
 /usr/include/eigen3/Eigen/src/Householder/BlockHouseholder.h \
 /usr/include/eigen3/Eigen/src/QR/HouseholderQR.h \
 /usr/include/eigen3/Eigen/src/QR/FullPivHouseholderQR.h \
 /usr/include/eigen3/Eigen/src/QR/ColPivHouseholderQR.h \
 /usr/include/eigen3/Eigen/src/QR/CompleteOrthogonalDecomposition.h \
 /usr/include/eigen3/Eigen/SVD \
 /usr/include/eigen3/Eigen/src/misc/RealSvd2x2.h \
 /usr/include/eigen3/Eigen/src/SVD/UpperBidiagonalization.h \
 /usr/include/eigen3/Eigen/src/SVD/SVDBase.h \
 /usr/include/eigen3/Eigen/src/SVD/JacobiSVD.h \
 /usr/include/eigen3/Eigen/src/SVD/BDCSVD.h \
 /usr/include/eigen3/Eigen/Geometry \
 /usr/include/eigen3/Eigen/src/Geometry/OrthoMethods.h \
 /usr/include/eigen3/Eigen/src/Geometry/EulerAngles.h \
 /usr/include/eigen3/Eigen/src/Geometry/Homogeneous.h \
 /usr/include/eigen3/Eigen/src/Geometry/RotationBase.h \
 /usr/include/eigen3/Eigen/src/Geometry/Rotation2D.h \
 /usr/include/eigen3/Eigen/src/Geometry/Quaternion.h \
 /usr/include/eigen3/Eigen/src/Geometry/AngleAxis.h \
 /usr/include/eigen3/Eigen/src/Geometry/Transform.h \
 /usr/include/eigen3/Eigen/src/Geometry/Translation.h \
 /usr/include/eigen3/Eigen/src/Geometry/Scaling.h \
 /usr/include/eigen3/Eigen/src/Geometry/Hyperplane.h \
 /usr/include/eigen3/Eigen/src/Geometry/ParametrizedLine.h \
 /usr/include/eigen3/Eigen/src/Geometry/AlignedBox.h \
 /usr/include/eigen3/Eigen/src/Geometry/Umeyama.h \
 /usr/include/eigen3/Eigen/src/Geometry/arch/Geometry_SIMD.h \
 /usr/include/eigen3/Eigen/Eigenvalues \
 /usr/include/eigen3/Eigen/src/Eigenvalues/Tridiagonalization.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/RealSchur.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/HessenbergDecomposition.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/EigenSolver.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/RealSchur.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/SelfAdjointEigenSolver.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/Tridiagonalization.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/GeneralizedSelfAdjointEigenSolver.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/HessenbergDecomposition.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/ComplexSchur.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/ComplexEigenSolver.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/ComplexSchur.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/RealQZ.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/GeneralizedEigenSolver.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/RealQZ.h \
 /usr/include/eigen3/Eigen/src/Eigenvalues/MatrixBaseEigenvalues.h \
 /usr/include/eigen3/Eigen/StdVector \
 /usr/include/eigen3/Eigen/src/StlSupport/StdVector.h \
 /usr/include/eigen3/Eigen/src/StlSupport/details.h \
 /usr/include/fcl/export.h /usr/include/fcl/math/bv/AABB-inl.h \
 /usr/include/fcl/math/motion/motion_base.h \
 /usr/include/fcl/math/motion/taylor_model/taylor_matrix.h \
 /usr/include/fcl/math/motion/taylor_model/taylor_vector.h \
 /usr/include/fcl/math/motion/taylor_model/interval_vector.h \
 /usr/include/fcl/math/motion/taylor_model/interval.h \
 /usr/include/c++/12/iostream \
 /usr/include/fcl/math/motion/taylor_model/interval-inl.h \
 /usr/include/fcl/math/motion/taylor_model/interval_vector-inl.h \
 /usr/include/fcl/math/motion/taylor_model/taylor_model.h \
 /usr/include/fcl/math/constants.h \
 /usr/include/fcl/math/motion/taylor_model/time_interval.h \
 /usr/include/fcl/math/motion/taylor_model/time_interval-inl.h \
 /usr/include/fcl/math/motion/taylor_model/taylor_model-inl.h \
 /usr/include/fcl/math/motion/taylor_model/taylor_vector-inl.h \
 /usr/include/fcl/math/motion/taylor_model/interval_matrix.h \
 /usr/include/fcl/math/motion/taylor_model/interval_matrix-inl.h \
 /usr/include/fcl/math/motion/taylor_model/taylor_matrix-inl.h \
 /usr/include/fcl/math/bv/RSS.h /usr/include/fcl/math/geometry.h \
 /usr/include/fcl/config.h /usr/include/fcl/math/triangle.h \
 /usr/include/fcl/math/geometry-inl.h /usr/include/fcl/math/bv/RSS-inl.h \
 /usr/include/fcl/math/motion/motion_base-inl.h \
 /usr/include/fcl/geometry/collision_geometry-inl.h \
 /usr/include/fcl/narrowphase/collision_object-inl.h \
 /usr/include/fcl/narrowphase/detail/distance_func_matrix.h \
 /usr/include/fcl/narrowphase/distance_request.h \
 /usr/include/fcl/narrowphase/gjk_solver_type.h \
 /usr/include/fcl/narrowphase/distance_request-inl.h \
 /usr/include/fcl/narrowphase/distance_result.h \
 /usr/include/fcl/narrowphase/distance_result-inl.h \
 /usr/include/fcl/narrowphase/detail/distance_func_matrix-inl.h \
 /usr/include/fcl/common/unused.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision_node.h \
 /usr/include/fcl/geometry/bvh/detail/BVH_front.h \
 /usr/include/c++/12/list /usr/include/c++/12/bits/stl_list.h \
 /usr/include/c++/12/bits/list.tcc \
 /usr/include/fcl/narrowphase/detail/traversal/traversal_recurse.h \
 /usr/include/fcl/narrowphase/detail/traversal/traversal_node_base.h \
 /usr/include/fcl/narrowphase/detail/traversal/traversal_node_base-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/collision_traversal_node_base.h \
 /usr/include/fcl/narrowphase/collision_request.h \
 /usr/include/fcl/narrowphase/collision_request-inl.h \
 /usr/include/fcl/narrowphase/collision_result.h /usr/include/c++/12/set \
 /usr/include/c++/12/bits/stl_set.h \
 /usr/include/c++/12/bits/stl_multiset.h \
 /usr/include/fcl/narrowphase/contact.h \
 /usr/include/fcl/narrowphase/contact-inl.h \
 /usr/include/fcl/narrowphase/cost_source.h \
 /usr/include/fcl/narrowphase/cost_source-inl.h \
 /usr/include/fcl/narrowphase/collision_result-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/collision_traversal_node_base-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/mesh_collision_traversal_node.h \
 /usr/include/fcl/math/bv/OBB.h /usr/include/fcl/math/bv/OBB-inl.h \
 /usr/include/fcl/math/bv/OBBRSS.h /usr/include/fcl/math/bv/OBBRSS-inl.h \
 /usr/include/fcl/math/bv/kIOS.h /usr/include/fcl/math/bv/kIOS-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/intersect.h \
 /usr/include/fcl/math/detail/polysolver.h \
 /usr/include/fcl/math/detail/polysolver-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/intersect-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/bvh_collision_traversal_node.h \
 /usr/include/fcl/geometry/bvh/BVH_model.h \
 /usr/include/fcl/math/bv/kDOP.h /usr/include/fcl/math/bv/kDOP-inl.h \
 /usr/include/fcl/geometry/bvh/BVH_internal.h \
 /usr/include/fcl/geometry/bvh/BV_node.h \
 /usr/include/fcl/geometry/bvh/BV_node_base.h \
 /usr/include/fcl/geometry/bvh/BV_node-inl.h \
 /usr/include/fcl/geometry/bvh/detail/BV_splitter.h \
 /usr/include/fcl/geometry/bvh/detail/BV_splitter_base.h \
 /usr/include/fcl/geometry/bvh/detail/BV_splitter-inl.h \
 /usr/include/fcl/geometry/bvh/detail/BV_fitter.h \
 /usr/include/fcl/geometry/bvh/detail/BV_fitter_base.h \
 /usr/include/fcl/geometry/bvh/detail/BV_fitter-inl.h \
 /usr/include/fcl/geometry/bvh/BVH_model-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/bvh_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/mesh_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/distance_traversal_node_base.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/distance_traversal_node_base-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/traversal_recurse-inl.h \
 /usr/include/c++/12/queue /usr/include/c++/12/deque \
 /usr/include/c++/12/bits/stl_deque.h /usr/include/c++/12/bits/deque.tcc \
 /usr/include/c++/12/bits/stl_queue.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision_node-inl.h \
 /usr/include/fcl/narrowphase/detail/gjk_solver_indep.h \
 /usr/include/fcl/narrowphase/contact_point.h \
 /usr/include/fcl/narrowphase/contact_point-inl.h \
 /usr/include/fcl/narrowphase/detail/gjk_solver_indep-inl.h \
 /usr/include/fcl/geometry/shape/triangle_p.h \
 /usr/include/fcl/geometry/shape/shape_base.h \
 /usr/include/fcl/geometry/shape/shape_base-inl.h \
 /usr/include/fcl/geometry/shape/triangle_p-inl.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/gjk.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/minkowski_diff.h \
 /usr/include/fcl/math/detail/project.h \
 /usr/include/fcl/math/detail/project-inl.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/minkowski_diff-inl.h \
 /usr/include/fcl/geometry/shape/box.h \
 /usr/include/fcl/geometry/shape/box-inl.h \
 /usr/include/fcl/geometry/shape/capsule.h \
 /usr/include/fcl/geometry/shape/capsule-inl.h \
 /usr/include/fcl/geometry/shape/cone.h \
 /usr/include/fcl/geometry/shape/cone-inl.h \
 /usr/include/fcl/geometry/shape/convex.h \
 /usr/include/fcl/geometry/shape/convex-inl.h /usr/include/c++/12/utility \
 /usr/include/c++/12/bits/stl_relops.h \
 /usr/include/fcl/geometry/shape/cylinder.h \
 /usr/include/fcl/geometry/shape/cylinder-inl.h \
 /usr/include/fcl/geometry/shape/ellipsoid.h \
 /usr/include/fcl/geometry/shape/ellipsoid-inl.h \
 /usr/include/fcl/geometry/shape/halfspace.h \
 /usr/include/fcl/geometry/shape/halfspace-inl.h \
 /usr/include/fcl/geometry/shape/plane.h \
 /usr/include/fcl/geometry/shape/plane-inl.h \
 /usr/include/fcl/geometry/shape/sphere.h \
 /usr/include/fcl/geometry/shape/sphere-inl.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/gjk-inl.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/epa.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/epa-inl.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/capsule_capsule.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/capsule_capsule-inl.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/sphere_box.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/sphere_box-inl.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/sphere_capsule.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/sphere_capsule-inl.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/sphere_cylinder.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/sphere_cylinder-inl.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/sphere_sphere.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/sphere_sphere-inl.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/sphere_triangle.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/sphere_triangle-inl.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/box_box.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/box_box-inl.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/halfspace.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/halfspace-inl.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/plane.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/plane-inl.h \
 /usr/include/fcl/narrowphase/detail/failed_at_this_configuration.h \
 /usr/include/c++/12/iomanip /usr/include/c++/12/locale \
 /usr/include/c++/12/bits/locale_facets_nonio.h /usr/include/c++/12/ctime \
 /usr/include/x86_64-linux-gnu/c++/12/bits/time_members.h \
 /usr/include/x86_64-linux-gnu/c++/12/bits/messages_members.h \
 /usr/include/libintl.h /usr/include/c++/12/bits/codecvt.h \
 /usr/include/c++/12/bits/locale_facets_nonio.tcc \
 /usr/include/c++/12/bits/locale_conv.h \
 /usr/include/c++/12/bits/quoted_string.h \
 /usr/include/fcl/narrowphase/detail/gjk_solver_libccd.h \
 /usr/include/fcl/narrowphase/detail/gjk_solver_libccd-inl.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/gjk_libccd.h \
 /usr/include/ccd/ccd.h /usr/include/ccd/vec3.h \
 /usr/include/ccd/compiler.h /usr/include/ccd/config.h \
 /usr/include/ccd/ccd_export.h /usr/include/ccd/quat.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/simplex.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/support.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/polytope.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/list.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/alloc.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/list.h \
 /usr/include/fcl/narrowphase/detail/convexity_based_algorithm/gjk_libccd-inl.h \
 /usr/include/c++/12/unordered_set \
 /usr/include/c++/12/bits/unordered_set.h \
 /usr/include/fcl/common/warning.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/bvh_distance_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/bvh_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/bvh_shape_distance_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/bvh_shape_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/mesh_distance_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/triangle_distance.h \
 /usr/include/fcl/narrowphase/detail/primitive_shape_algorithm/triangle_distance-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/mesh_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/mesh_conservative_advancement_traversal_node.h \
 /usr/include/fcl/math/motion/tbv_motion_bound_visitor.h \
 /usr/include/fcl/math/motion/bv_motion_bound_visitor.h \
 /usr/include/fcl/math/motion/tbv_motion_bound_visitor-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/conservative_advancement_stack_data.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/conservative_advancement_stack_data-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/mesh_conservative_advancement_traversal_node-inl.h \
 /usr/include/fcl/math/motion/triangle_motion_bound_visitor.h \
 /usr/include/fcl/math/motion/spline_motion.h \
 /usr/include/fcl/math/motion/spline_motion-inl.h \
 /usr/include/fcl/math/motion/screw_motion.h \
 /usr/include/fcl/math/motion/screw_motion-inl.h \
 /usr/include/fcl/math/motion/interp_motion.h \
 /usr/include/fcl/math/motion/interp_motion-inl.h \
 /usr/include/fcl/math/motion/translation_motion.h \
 /usr/include/fcl/math/motion/translation_motion-inl.h \
 /usr/include/fcl/math/motion/triangle_motion_bound_visitor-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/mesh_shape_distance_traversal_node.h \
 /usr/include/fcl/geometry/shape/utility.h \
 /usr/include/fcl/geometry/shape/utility-inl.h \
 /usr/include/fcl/math/bv/utility.h \
 /usr/include/fcl/math/bv/utility-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/mesh_shape_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/mesh_shape_conservative_advancement_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/mesh_shape_conservative_advancement_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/shape_bvh_distance_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/shape_bvh_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/shape_distance_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/shape_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/shape_conservative_advancement_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/shape_conservative_advancement_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/shape_mesh_distance_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/shape_mesh_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/shape_mesh_conservative_advancement_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/distance/shape_mesh_conservative_advancement_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/distance/mesh_octree_distance_traversal_node.h \
 /usr/include/fcl/geometry/octree/octree.h /usr/include/octomap/octomap.h \
 /usr/include/octomap/octomap_types.h /usr/include/inttypes.h \
 /usr/include/octomap/math/Vector3.h /usr/include/octomap/math/Pose6D.h \
 /usr/include/octomap/math/Vector3.h \
 /usr/include/octomap/math/Quaternion.h \
 /usr/include/octomap/octomap_deprecated.h \
 /usr/include/octomap/Pointcloud.h /usr/include/octomap/octomap_types.h \
 /usr/include/octomap/ScanGraph.h /usr/include/octomap/OcTree.h \
 /usr/include/octomap/OccupancyOcTreeBase.h \
 /usr/include/octomap/octomap_utils.h \
 /usr/include/octomap/OcTreeBaseImpl.h /usr/include/c++/12/iterator \
 /usr/include/c++/12/bits/stream_iterator.h /usr/include/c++/12/stack \
 /usr/include/c++/12/bits/stl_stack.h /usr/include/c++/12/bitset \
 /usr/include/octomap/OcTreeKey.h /usr/include/c++/12/ciso646 \
 /usr/include/c++/12/tr1/unordered_set \
 /usr/include/c++/12/tr1/type_traits \
 /usr/include/c++/12/tr1/functional_hash.h \
 /usr/include/c++/12/tr1/hashtable.h \
 /usr/include/c++/12/tr1/hashtable_policy.h \
 /usr/include/c++/12/tr1/unordered_set.h \
 /usr/include/c++/12/tr1/unordered_map \
 /usr/include/c++/12/tr1/unordered_map.h \
 /usr/include/octomap/OcTreeIterator.hxx \
 /usr/include/octomap/OcTreeBaseImpl.hxx \
 /usr/include/octomap/AbstractOccupancyOcTree.h \
 /usr/include/octomap/AbstractOcTree.h /usr/include/c++/12/fstream \
 /usr/include/x86_64-linux-gnu/c++/12/bits/basic_file.h \
 /usr/include/x86_64-linux-gnu/c++/12/bits/c++io.h \
 /usr/include/c++/12/bits/fstream.tcc /usr/include/octomap/OcTreeNode.h \
 /usr/include/octomap/OcTreeDataNode.h \
 /usr/include/octomap/OcTreeDataNode.hxx \
 /usr/include/octomap/OccupancyOcTreeBase.hxx \
 /usr/include/octomap/MCTables.h \
 /usr/include/fcl/geometry/octree/octree-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/octree_solver.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/octree_solver-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/distance/mesh_octree_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/distance/octree_distance_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/distance/octree_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/distance/octree_mesh_distance_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/distance/octree_mesh_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/distance/octree_shape_distance_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/distance/octree_shape_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/distance/shape_octree_distance_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/distance/shape_octree_distance_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/distance-inl.h \
 /usr/include/fcl/narrowphase/collision.h \
 /usr/include/fcl/narrowphase/collision-inl.h \
 /usr/include/fcl/narrowphase/detail/collision_func_matrix.h \
 /usr/include/fcl/narrowphase/detail/collision_func_matrix-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/bvh_shape_collision_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/bvh_shape_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/mesh_continuous_collision_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/mesh_continuous_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/mesh_shape_collision_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/mesh_shape_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/shape_bvh_collision_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/shape_bvh_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/shape_collision_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/shape_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/shape_mesh_collision_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/collision/shape_mesh_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/collision/mesh_octree_collision_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/collision/mesh_octree_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/collision/octree_collision_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/collision/octree_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/collision/octree_mesh_collision_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/collision/octree_mesh_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/collision/octree_shape_collision_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/collision/octree_shape_collision_traversal_node-inl.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/collision/shape_octree_collision_traversal_node.h \
 /usr/include/fcl/narrowphase/detail/traversal/octree/collision/shape_octree_collision_traversal_node-inl.h \
 /work/main/xpbd/include/xpbd/types.hpp /usr/include/eigen3/Eigen/Core
