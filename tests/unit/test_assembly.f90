!> Slot assembly against a plain scatter-add on a random mesh: same nodal
!> forces (to rounding), every slot used once, and bitwise the same result
!> whatever the element order of the slots' writing.
program test_assembly
    use xd_kinds, only: wp, dp
    use xd_testing, only: check, test_summary
    use xd_solver_assembly, only: assembly_t, build_assembly, assemble
    implicit none
    integer, parameter :: nnode = 500, nel = 700
    integer :: conn(8, nel), e, k, nd
    real(wp) :: fslot(3, 8*nel), f(3, nnode), fref(3, nnode), f2(3, nnode)
    real :: r(8, nel)
    real(wp) :: rf(3, 8*nel)
    type(assembly_t) :: asm

    call random_seed(put=[(4242 + k, k=1, 64)])
    call random_number(r)
    conn = 1 + int(r*nnode)
    call random_number(rf)
    fslot = rf - 0.5_wp
    call build_assembly(nnode, conn, asm)
    call check(asm%ptr(nnode + 1) - 1 == 8*nel, 'assembly: every incidence has a slot')
    fref = 0
    do e = 1, nel
        do k = 1, 8
            nd = conn(k, e)
            fref(:, nd) = fref(:, nd) + fslot(:, 8*(e - 1) + k)
        end do
    end do
    call assemble(asm, fslot, f)
    call check(maxval(abs(f - fref)) < 1.0e-12_wp, 'assembly: nodal sums equal a plain scatter-add')
    call check(all(f == fref), 'assembly: sums in element order, bitwise equal to the serial scatter')
    call assemble(asm, fslot, f2)
    call check(all(f2 == f), 'assembly: repeatable bitwise')
    call check(abs(sum(real(f, dp)) - sum(real(fslot, dp))) < 1.0e-9_dp, 'assembly: total force conserved')
    call test_summary()
end program test_assembly
